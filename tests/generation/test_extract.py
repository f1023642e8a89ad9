"""The code is found in whatever the model wrapped it in."""

from __future__ import annotations

from skillwright.generation.extract import extract_code


def test_a_fenced_python_block_is_taken_without_the_prose_around_it() -> None:
    answer = "Here is the skill:\n```python\nimport rclpy\nclass A:\n    pass\n```\nEnjoy."
    extracted = extract_code(answer)
    assert extracted.code == "import rclpy\nclass A:\n    pass\n"
    assert extracted.method == "fenced"


def test_the_block_defining_a_class_wins_over_a_longer_usage_example() -> None:
    usage = "x = 1\n" * 20
    answer = f"```python\nclass Skill:\n    x = 1\n```\nUse it:\n```python\n{usage}```"
    assert extract_code(answer).code.startswith("class Skill:")


def test_an_untagged_fence_counts_as_python() -> None:
    assert extract_code("```\nclass A:\n    pass\n```").code == "class A:\n    pass\n"


def test_a_block_in_another_language_is_not_taken() -> None:
    answer = "```bash\nros2 run pkg node\n```\nimport rclpy\n"
    extracted = extract_code(answer)
    assert extracted.code == "import rclpy\n"
    assert extracted.method == "bare"


def test_an_answer_cut_off_inside_its_fence_keeps_what_was_written() -> None:
    extracted = extract_code("Sure.\n```python\nclass A:\n    def f(self):\n        return 1")
    assert extracted.code == "class A:\n    def f(self):\n        return 1\n"
    assert extracted.method == "unclosed fence"


def test_bare_code_loses_only_the_leading_prose() -> None:
    extracted = extract_code("The skill follows.\n\nfrom x import y\n\nclass A:\n    pass\n")
    assert extracted.code == "from x import y\n\nclass A:\n    pass\n"


def test_an_answer_without_code_gives_nothing() -> None:
    assert extract_code("I cannot help with that.").method == "empty"
    assert extract_code("").code == ""
