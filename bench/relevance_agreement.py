"""Relevance verdicts against the Cap2Skill paper's own filter, on the paper's robot.

The paper's raw report lists 107 interfaces of a simulated ROS 2 robot; its filtered report
(after the paper's GPT-4o relevance check) keeps 33. This script judges the 107 with one
of our engines and prints precision and recall of our ``control`` set against those 33,
then every disagreement with our judgement of who is right (from
``tests/interfaces/labels/paper_relevance.yaml``), and the same figures against the
judged labels (the paper's selection corrected where we think it was wrong).

    python bench/relevance_agreement.py                        # rules engine, no model
    python bench/relevance_agreement.py --engine llm [--model ID] [--models FILE]

The ``llm`` engine needs a generation model's weights in the models directory (see
``skillwright models list``); nothing is downloaded. Its answers are cached like those of
``skillwright inventory describe``, so a second run is quick. Needs ``../shared`` beside the
repository.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
REPORTS = ROOT.parent / "shared" / "data" / "cap2skill" / "interface-reports"
RAW_REPORT = REPORTS / "ros2_system_report.json"
FILTERED_REPORT = REPORTS / "ros2_system_report_with_descriptions.json"
LABELS = ROOT / "tests" / "interfaces" / "labels" / "paper_relevance.yaml"


def read_report(path: Path = RAW_REPORT) -> list[Any]:
    """The report's interfaces, imported as ``skillwright discover`` imports a report."""
    from skillwright.interfaces.load import load_inventory

    return list(load_inventory(path).interfaces)


def kept_names(path: Path = FILTERED_REPORT) -> set[str]:
    """Names of the interfaces the paper's filter kept."""
    return {i.name for i in read_report(path)}


def load_labels(path: Path = LABELS) -> dict[str, Any]:
    """The checked-in judgement of every disagreement between the rules engine and the paper."""
    import yaml

    document = yaml.safe_load(path.read_text(encoding="utf-8"))
    assert isinstance(document, dict)
    return document


def judged_control(interfaces: list[Any], kept: set[str], labels: Mapping[str, Any]) -> set[str]:
    """The paper's selection, corrected where the labels say the paper was wrong."""
    judged = set(kept)
    for name, label in labels["disagreements"].items():
        if label["right"] == "rules":
            if label["rules"] == "control":
                judged.add(name)
            else:
                judged.discard(name)
    return judged & {i.name for i in interfaces}


def verdicts(
    engine: str, interfaces: list[Any], model: str | None = None, models: Path | None = None
) -> Any:
    """Name -> Relevance from the chosen engine."""
    from skillwright.interfaces.relevance import relevance_by_rules

    if engine == "rules":
        return {i.name: relevance_by_rules(i) for i in interfaces}
    from skillwright.interfaces.enrich import LlmEngine, default_cache, enrich
    from skillwright.interfaces.inventory import Inventory, Resource
    from skillwright.llm import load_generator, load_registry

    generator = load_generator(load_registry(models), model)
    try:
        inventory = Inventory(resource=Resource(name="Cap2Skill robot"), interfaces=interfaces)
        report = enrich(inventory, LlmEngine(generator), cache=default_cache(), progress=_progress)
    finally:
        generator.close()
    print(file=sys.stderr)
    for note in report.notes:
        print(f"note: {note}", file=sys.stderr)
    return {i.name: i.relevance for i in report.inventory.interfaces if i.relevance is not None}


def _progress(done: int, total: int, name: str) -> None:
    print(f"\r{done}/{total} {name:60}", end="", file=sys.stderr, flush=True)


def _print_agreement(title: str, result: Any) -> None:
    print(
        f"{title:28} control {len(result.both) + len(result.only_ours):3}  "
        f"precision {result.precision:.2f}  recall {result.recall:.2f}  "
        f"disagreements {len(result.disagreements)}"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--engine", choices=["rules", "llm"], default="rules")
    parser.add_argument("--model", help="generation model id or alias (llm engine)")
    parser.add_argument("--models", type=Path, help="a models.toml to use (llm engine)")
    args = parser.parse_args(argv)
    if not RAW_REPORT.is_file():
        print(f"skipped: {RAW_REPORT} not found")
        return 0
    from skillwright.interfaces.relevance import agreement

    interfaces = read_report()
    kept = kept_names()
    labels = load_labels()
    from skillwright.errors import SkillwrightError

    try:
        judged = verdicts(args.engine, interfaces, args.model, args.models)
    except SkillwrightError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    against_paper = agreement(judged, kept)
    against_labels = agreement(judged, judged_control(interfaces, kept, labels))
    print(f"engine {args.engine}: {len(interfaces)} interfaces, the paper keeps {len(kept)}")
    if args.engine == "llm":
        fallbacks = sum(v.engine == "rules" for v in judged.values())
        print(f"verdicts by the model: {len(judged) - fallbacks}, rules fallbacks: {fallbacks}")
    _print_agreement("vs the paper's filter", against_paper)
    _print_agreement("vs the judged labels", against_labels)
    print()
    print("disagreements with the paper (ours / paper; who we think is right):")
    documented = labels["disagreements"]
    for name in sorted(against_paper.disagreements):
        ours = "control" if name in against_paper.only_ours else "infrastructure"
        theirs = "infrastructure" if ours == "control" else "control"
        label = documented.get(name)
        if label is not None and label["rules"] == ours:
            verdict = f"{label['right']} right: {label['why']}"
        else:
            verdict = "not judged yet (differs from the rules engine)"
        print(f"  {name:55} {ours:>14} / {theirs:<14} {verdict}")
        print(f"  {'':55} reason: {judged[name].reason}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
