"""Write free-text descriptions of written robots' interfaces with the local model.

A report "with descriptions" (the Cap2Skill tool's format, and so possibly the robot this
project's retrieval is judged on) carries a language model's free text for every interface,
in four sections: purpose, module, tasks, usage. Our written robots
(``tests/retrieval/robots``) had none, so the benchmark never saw what such text does to the
ranking. This script asks the local generation model for that text, one interface at a
time, for every retrieval candidate of each robot given, and stores it in
``tests/retrieval/robots/described/<robot>.json``; the labelled sets read it through the
report import's parser (``load_set(name, described=True)``) and ``bench/bench_retrieval.py``
scores them.

    python bench/describe_robots.py tb3manip tiago [--model ID]

About 20 s per interface on two cores with the default model (88 candidates of the TurtleBot3
in 27 minutes); what is already in a file is kept, so an interrupted run resumes. It needs
the model's weights in the models directory; nothing is downloaded, and ``make bench`` does
not run it.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the written robots live with the tests

SYSTEM = (
    "You write documentation for the ROS 2 interfaces of a mobile robot, for engineers who "
    "build robot skills. For the interface you are given, answer in exactly this layout, "
    "with one or two '-' items under each heading:\n"
    "Purpose of the ROS2 Element:\n- what it does and what it is typically used for\n"
    "Mobile Robot Module:\n- the module of a mobile robot it belongs to\n"
    "Relevance for Specific Tasks:\n- the tasks and problems it helps with\n"
    "Usage in the ROS2 System:\n- which nodes or programs publish, subscribe, call or serve it"
)
"""The instruction: the four sections the report import parses, in our own words."""

MAX_TOKENS = 260


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="+", help="written robots (tests/retrieval/robots)")
    parser.add_argument("--model", help="generation model id (default: models.toml's)")
    args = parser.parse_args(argv)

    from tests.retrieval.labelled import DESCRIBED_DIR, WRITTEN, load_set

    from skillwright.errors import SkillwrightError
    from skillwright.fileio import write_atomic
    from skillwright.interfaces.enrich import trimmed_definition
    from skillwright.llm import load_generator
    from skillwright.llm.base import GenerationOptions, Prompt
    from skillwright.llm.config import load_registry
    from skillwright.retrieval.retrieve import candidates

    unknown = [name for name in args.robots if name not in WRITTEN]
    if unknown:
        print(f"unknown robot(s) {', '.join(unknown)}; choose from {', '.join(WRITTEN)}")
        return 2
    try:
        generator = load_generator(load_registry(), args.model)
    except SkillwrightError as error:  # an unknown id or a model not installed
        print(f"error: {error}")
        return 2
    options = GenerationOptions(max_tokens=MAX_TOKENS, temperature=0.0)
    try:
        for name in args.robots:
            path = DESCRIBED_DIR / f"{name}.json"
            document = (
                json.loads(path.read_text(encoding="utf-8"))
                if path.exists()
                else {"model": generator.model_id, "system": SYSTEM, "descriptions": {}}
            )
            texts: dict[str, str] = document["descriptions"]
            pool = candidates(load_set(name).inventory)
            todo = [i for i in pool if f"{i.kind} {i.name}" not in texts]
            started = time.perf_counter()
            for done, interface in enumerate(todo, 1):
                question = (
                    f"ROS 2 {interface.kind} `{interface.name}` of type "
                    f"`{interface.type_name}`.\nDefinition:\n{trimmed_definition(interface)}"
                )
                text = generator.stream(Prompt.chat(question, system=SYSTEM), options).text()
                texts[f"{interface.kind} {interface.name}"] = text.strip()
                document["descriptions"] = dict(sorted(texts.items()))
                write_atomic(path, json.dumps(document, indent=1, ensure_ascii=False) + "\n")
                print(
                    f"{name} {done}/{len(todo)} {interface.name} "
                    f"({time.perf_counter() - started:.0f} s)",
                    flush=True,
                )
    finally:
        generator.close()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
