"""`skillwright retrieve` on the shipped MR-1 capabilities and recording."""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner

from skillwright.cli import main
from skillwright.console import err_console, out_console
from skillwright.interfaces.inventory import InfrastructureFlag, Interface, Inventory, Resource
from skillwright.interfaces.load import load_inventory
from skillwright.interfaces.sources.report import report_from_inventory
from tests.conftest import REPO_ROOT, SHIPPED_CAPABILITIES
from tests.interfaces.test_load import cut_recording

MR1 = str(SHIPPED_CAPABILITIES / "recordings" / "mr1")
ROTATE = ["--capability", str(SHIPPED_CAPABILITIES / "rotate.ttl")]
ROTATE_SPEC = ["--spec", str(SHIPPED_CAPABILITIES / "rotate.spec.yaml")]


@pytest.fixture(autouse=True)
def fresh_consoles(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """Consoles created inside the test, so that they write to the runner's streams."""
    monkeypatch.setenv("COLUMNS", "250")
    out_console.cache_clear()
    err_console.cache_clear()
    yield
    out_console.cache_clear()
    err_console.cache_clear()


def invoke(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, ["retrieve", *args])
    return result.exit_code, result.stdout, result.stderr


def table_names(output: str) -> list[str]:
    return [
        line.split("│")[1].strip()
        for line in output.splitlines()
        if line[:1].isdigit() and "│" in line
    ]


def test_lexical_ranking_prints_a_table_with_reasons_and_a_summary() -> None:
    code, out, err = invoke(*ROTATE, *ROTATE_SPEC, "--interfaces", MR1, "--no-dense")
    assert code == 0, err
    names = table_names(out)
    assert len(names) == 4
    assert "/cmd_vel" in names
    [row] = [line for line in out.splitlines() if "/cmd_vel " in line]
    assert "geometry_msgs/msg/Twist" in row
    assert " - " in row  # no dense score without a model
    assert "4 of 38 candidate(s); 39 infrastructure interface(s) left out (--all)" in out
    assert "ranking: lexical" in out
    assert "ranked 38 interface(s)" in err


def test_a_recording_cut_short_is_warned_about_before_the_ranking(tmp_path: Path) -> None:
    cut = cut_recording(tmp_path)
    code, out, err = invoke(*ROTATE, "--interfaces", str(cut))
    assert code == 0, err
    assert f"warning: {cut}: read only up to byte " in err
    assert table_names(out)


def test_k_sets_the_number_of_hits() -> None:
    code, out, _ = invoke(*ROTATE, "--interfaces", MR1, "--no-dense", "-k", "7")
    assert code == 0
    assert len(table_names(out)) == 7


def test_json_holds_every_hit_field_and_what_was_ranked() -> None:
    code, out, _ = invoke(*ROTATE, *ROTATE_SPEC, "--interfaces", MR1, "--no-dense", "--json")
    assert code == 0
    document = json.loads(out)
    assert document["capability"].endswith("/rotate")
    assert document["method"] == "lexical"
    assert document["embedding_model"] is None
    assert document["candidates"] == 38
    assert document["k"] == 4
    [first, *_] = document["hits"]
    assert set(first) >= {"name", "kind", "type_name", "score", "dense", "lexical", "reason"}
    scores = [h["score"] for h in document["hits"]]
    assert len(scores) == 4


def test_all_ranks_infrastructure_interfaces_too() -> None:
    code, out, _ = invoke(*ROTATE, "--interfaces", MR1, "--no-dense", "--all", "--json")
    assert code == 0
    assert json.loads(out)["candidates"] == 77


def test_a_saved_inventory_is_accepted(tmp_path: Path) -> None:
    saved = tmp_path / "inventory.json"
    result = CliRunner().invoke(main, ["discover", MR1, "-o", str(saved)])
    assert result.exit_code == 0, result.output
    code, out, _ = invoke(*ROTATE, "--interfaces", str(saved), "--no-dense", "--json")
    assert code == 0
    assert json.loads(out)["candidates"] == 38


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--interfaces", "no/such/bag"], "interface source no/such/bag: no such file"),
        (
            ["--capability", "nothing.ttl", "--interfaces", MR1],
            "nothing.ttl",
        ),
        (["--spec", "missing.spec.yaml", "--interfaces", MR1], "missing.spec.yaml"),
        (["--interfaces", MR1, "-k", "0"], "0 is not in the range x>=1"),
    ],
)
def test_bad_input_is_one_error_line_with_exit_status_2(args: list[str], message: str) -> None:
    full = [*ROTATE, "--no-dense", *args] if "--capability" not in args else ["--no-dense", *args]
    code, _, err = invoke(*full)
    assert code == 2
    assert message in err
    assert "Traceback" not in err


def test_an_inventory_of_infrastructure_only_says_to_use_all(tmp_path: Path) -> None:
    inventory = Inventory(
        resource=Resource(name="plumbing"),
        interfaces=[
            Interface(
                name="/rosout",
                kind="topic",
                type_name="rcl_interfaces/msg/Log",
                infrastructure=InfrastructureFlag(rule="rosout", reason="log output"),
            )
        ],
    )
    path = tmp_path / "inventory.json"
    path.write_text(inventory.model_dump_json())
    code, _, err = invoke(*ROTATE, "--interfaces", str(path), "--no-dense")
    assert code == 2
    assert "none of its 1 interface(s) is a candidate; --all ranks" in err


def test_a_missing_embedding_model_suggests_ranking_without_it(tmp_path: Path) -> None:
    models = tmp_path / "models.toml"
    models.write_text(
        '[defaults]\nembedding = "gone"\n\n[[embedding]]\nid = "gone"\n'
        f'path = "{tmp_path / "no-model"}"\n'
    )
    code, _, err = invoke(*ROTATE, "--interfaces", MR1, "--models", str(models), "--dense")
    assert code == 2
    assert "embedding model 'gone'" in err
    assert "leave out --dense" in err


@pytest.mark.parametrize("flags", [[], ["--no-dense"]])
def test_by_default_the_embedding_model_is_never_loaded(flags: list[str]) -> None:
    code = (
        "import sys\n"
        "from skillwright.cli import main\n"
        f"main(['retrieve', '--capability', {str(SHIPPED_CAPABILITIES / 'rotate.ttl')!r},"
        f" '--interfaces', {MR1!r}, *{flags!r}, '--json'], standalone_mode=False)\n"
        "assert 'skillwright.llm.bert' not in sys.modules and 'tokenizers' not in sys.modules\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO_ROOT, check=False
    )
    assert result.returncode == 0, result.stderr


@pytest.mark.slow
def test_hybrid_ranking_loads_minilm_and_fills_the_dense_column(tmp_path: Path) -> None:
    env_cache = {"SKILLWRIGHT_CACHE_DIR": str(tmp_path)}
    result = CliRunner(env=env_cache).invoke(
        main, ["retrieve", *ROTATE, *ROTATE_SPEC, "--interfaces", MR1, "--dense", "--json"]
    )
    assert result.exit_code == 0, result.stderr
    document = json.loads(result.stdout)
    assert document["method"] == "hybrid"
    assert document["embedding_model"] == "all-minilm-l6-v2"
    assert all(h["dense"] is not None for h in document["hits"])
    assert "loading embedding model all-minilm-l6-v2" in result.stderr


def scripted_reranker(monkeypatch: pytest.MonkeyPatch, needed: set[str]) -> list[str | None]:
    """Makes `--rerank` load a scripted model that calls ``needed`` needed; returns the ids
    it was loaded with."""
    import skillwright.llm
    from tests.retrieval.test_rerank import NEEDED, ScriptedModel

    loads: list[str | None] = []

    def load(_registry: object, model_id: str | None = None, **_: object) -> ScriptedModel:
        loads.append(model_id)
        return ScriptedModel(dict.fromkeys(needed, NEEDED), model_id="scripted")

    monkeypatch.setattr(skillwright.llm, "load_generator", load)
    return loads


def test_rerank_puts_the_models_needed_first_and_prints_its_reasons(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setenv("SKILLWRIGHT_CACHE_DIR", str(tmp_path))
    loads = scripted_reranker(monkeypatch, {"/odom"})
    args = [*ROTATE, *ROTATE_SPEC, "--interfaces", MR1, "--no-dense", "--rerank"]
    code, out, err = invoke(*args)
    assert code == 0, err
    assert table_names(out)[0] == "/odom"
    assert "It commands the base velocity." in out
    assert "re-ranked by scripted" in out
    assert "re-ranked: 1 of 8 judged needed; 8 asked" in err
    code, out, err = invoke(*args, "--json", "--model", "coder")
    assert code == 0, err
    document = json.loads(out)
    assert document["rerank"]["cached"] == 8
    assert document["hits"][0]["needed"] is True
    assert document["hits"][1]["judgement"] == "The skill never reads images."
    assert loads == ["qwen2.5-coder-1.5b-instruct"] * 2  # the default, then by alias


def test_a_model_without_rerank_is_refused() -> None:
    code, _, err = invoke(*ROTATE, "--interfaces", MR1, "--no-dense", "--model", "coder")
    assert code == 2
    assert "--model names the re-ranking model; add --rerank" in err


def test_a_report_that_cannot_tell_two_velocity_topics_apart_is_warned_about(
    tmp_path: Path,
) -> None:
    # the Stretch as the reference tool's report lists it: its driver's /stretch/cmd_vel
    # beside Nav2's /cmd_vel, and no counts to say which one the driver reads
    base = load_inventory(Path(MR1))
    velocity = base.interface("/cmd_vel")
    driver = velocity.model_copy(update={"name": "/stretch/cmd_vel"})
    inventory = base.model_copy(update={"interfaces": [*base.interfaces, driver]})
    document, _ = report_from_inventory(inventory)
    report = tmp_path / "stretch_report.json"
    report.write_text(json.dumps(document))
    code, out, err = invoke(*ROTATE, *ROTATE_SPEC, "--interfaces", str(report), "--no-dense")
    assert code == 0, err
    assert "/cmd_vel" in table_names(out)
    assert (
        "warning: /cmd_vel (geometry_msgs/msg/Twist) was chosen over /stretch/cmd_vel of the "
        "same type by its name alone" in " ".join(err.split())
    )
    code, out, err = invoke(*ROTATE, *ROTATE_SPEC, "--interfaces", MR1, "--no-dense")
    assert code == 0, err
    assert "warning" not in err  # the recording's one velocity topic has no twin
