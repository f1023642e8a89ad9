"""``skillwright check``: run the static checks on a skill file."""

from __future__ import annotations

import sys
from collections import Counter
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

import click

from skillwright.cli_options import (
    bind_option,
    capability_options,
    interfaces_option,
    spec_option,
)

if TYPE_CHECKING:
    from rich.console import Console

    from skillwright.rules.finding import Finding
    from skillwright.validation.model import CheckReport

__all__ = ["check", "print_findings", "rules", "selection_options"]

F = TypeVar("F", bound=Callable[..., object])


def print_findings(console: Console, path: object, findings: Sequence[Finding]) -> None:
    """Prints findings compiler-style: ``path:line:col: severity CODE [group] message``, one
    line each whatever the terminal's width (editors and CI logs parse these lines);
    ``skillwright check --explain CODE`` says more of a rule."""
    from rich.markup import escape

    for finding in findings:
        style = "red" if finding.severity == "error" else "yellow"
        code = f"{finding.code} " if finding.code else ""
        console.print(
            f"{escape(str(path))}:{finding.line}:{finding.column}: [{style}]{finding.severity}[/] "
            f"{code}{escape(f'[{finding.check}]')} {escape(finding.message)}",
            highlight=False,
            soft_wrap=True,
        )


def _explain(context: click.Context, _: click.Parameter, code: str | None) -> None:
    """``--explain CODE``: the rule's documentation, then exit (nothing else is needed)."""
    if code is None or context.resilient_parsing:
        return
    from skillwright.console import out_console
    from skillwright.errors import InvalidArgumentError
    from skillwright.rules.registry import UnknownRuleError, get

    try:
        rule = get(code)
    except UnknownRuleError:
        raise InvalidArgumentError(
            f"--explain {code}: no rule has that code or name; `skillwright rules` lists them"
        ) from None
    out_console().print(rule.explain(), highlight=False, markup=False, soft_wrap=True)
    context.exit(0)


def selection_options(function: F) -> F:
    """``--select`` and ``--ignore`` (as ``select`` and ``ignore``), repeatable."""
    function = click.option(
        "--ignore",
        multiple=True,
        metavar="RULES",
        help="Leave out these rules: codes (SW113), blocks (SW1), groups (interfaces) or names, "
        "comma-separated or repeated; added to the project's ignore.",
    )(function)
    return click.option(
        "--select",
        multiple=True,
        metavar="RULES",
        help="Only these rules (as --ignore takes them; ALL for every one); in place of the "
        "project's select ([tool.skillwright] in pyproject.toml).",
    )(function)


@click.command("check")
@click.argument("skill_file", type=click.Path(path_type=Path))
@capability_options
@spec_option(required=True)
@interfaces_option(required=False, extra_help=" Without it, interface grounding is not checked.")
@click.option(
    "--retrieved",
    multiple=True,
    metavar="NAME",
    help="An interface retrieval chose (repeatable): enables the used-versus-retrieved check.",
)
@bind_option
@selection_options
@click.option(
    "--fix",
    is_flag=True,
    help="Put the safe fixes into SKILL_FILE (fixes that only write what the code means in "
    "the form the API takes), then report what is left.",
)
@click.option(
    "--unsafe-fixes",
    is_flag=True,
    help="With --fix, also the unsafe ones (they decide something the code did not say: a "
    "timeout, a wait, a command repeated), which can change what the robot does; review them.",
)
@click.option(
    "--explain",
    metavar="CODE",
    is_eager=True,
    expose_value=False,
    callback=_explain,
    help="Explain a rule (its code or name) and exit.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON.")
def check(
    skill_file: Path,
    capability_file: Path,
    capability_iri: str | None,
    ontology_files: tuple[Path, ...],
    spec_file: Path,
    source: Path | None,
    retrieved: tuple[str, ...],
    bind: dict[str, str],
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    fix: bool,
    unsafe_fixes: bool,
    as_json: bool,
) -> None:
    """Check SKILL_FILE statically against its capability, spec and the robot's interfaces.

    Every finding carries its rule's code; `skillwright rules` lists the rules and
    `--explain CODE` explains one. Exit status 0 when no check fails, 1 when a check finds an
    error, 2 for bad input.
    """
    from skillwright.capability.reader import load_capability
    from skillwright.console import err_console, out_console, print_model_json
    from skillwright.errors import InputFileError, InputFileNotFoundError, InvalidArgumentError
    from skillwright.rules.settings import project_selection
    from skillwright.spec.loader import load_spec
    from skillwright.validation.static import check_skill

    if unsafe_fixes and not fix:
        raise InvalidArgumentError("--unsafe-fixes goes with --fix")
    if skill_file.is_dir():
        raise InputFileError(f"skill file {skill_file}: is a folder; give the skill's .py file")
    if not skill_file.is_file():
        raise InputFileNotFoundError(f"skill file {skill_file}: no such file; check the path")
    try:
        source_text = skill_file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise InputFileError(f"skill file {skill_file}: cannot be read as UTF-8 text") from error
    selection = project_selection(skill_file).narrowed(select, ignore)
    capability = load_capability(
        capability_file, capability_iri=capability_iri, ontologies=ontology_files
    ).capability
    skill_spec = load_spec(spec_file)
    catalog = None
    if source is not None:
        from skillwright.console import warn
        from skillwright.interfaces.load import load_inventory, read_warnings
        from skillwright.validation.catalog import catalog_from_inventory

        inventory = load_inventory(source)
        warn(read_warnings(inventory))
        catalog = catalog_from_inventory(inventory)

    def checked(text: str) -> CheckReport:
        report = check_skill(
            text,
            capability=capability,
            spec=skill_spec,
            catalog=catalog,
            retrieved=retrieved,
            path=str(skill_file),
            bindings=bind,
        )
        return report.model_copy(update={"findings": selection.filter(report.findings)})

    report = checked(source_text)
    if fix:
        report, fixed = _fix(skill_file, source_text, report, checked, unsafe=unsafe_fixes)
        if fixed and not as_json:
            err_console().print(_fixed_summary(fixed), highlight=False, soft_wrap=True)
    if as_json:
        print_model_json(report)
    else:
        console = out_console()
        print_findings(console, report.path, report.findings)
        errors = sum(f.severity == "error" for f in report.findings)
        warnings = len(report.findings) - errors
        verdict = "passed" if report.passed else "failed"
        grounding = "" if catalog is not None else " (interfaces not checked: no --interfaces)"
        offered = _fixes_offered(report.findings, unsafe=unsafe_fixes)
        console.print(
            f"{report.path}: {verdict}, {errors} error(s), {warnings} warning(s){grounding}"
            + offered,
            soft_wrap=True,
            highlight=False,
        )
    if not report.passed:
        sys.exit(1)


_FIX_ROUNDS = 10
"""Rounds of fixing and checking again at most (each round's fixes can make new ones)."""


def _fix(
    skill_file: Path,
    text: str,
    report: CheckReport,
    checked: Callable[[str], CheckReport],
    *,
    unsafe: bool,
) -> tuple[CheckReport, list[Finding]]:
    """Fixes the file round by round until no fix applies; writes it once, atomically."""
    from skillwright.fileio import write_atomic
    from skillwright.rules.fixes import apply_fixes

    applied: list[Finding] = []
    current = text
    for _ in range(_FIX_ROUNDS):
        fixed, done = apply_fixes(current, report.findings, unsafe=unsafe)
        if not done:
            break
        applied += done
        current = fixed
        report = checked(current)
    if current != text:
        write_atomic(skill_file, current)
    return report, applied


def _fixed_summary(fixed: Sequence[Finding]) -> str:
    counts = Counter(f.code for f in fixed)
    listed = ", ".join(f"{code} x{n}" if n > 1 else code for code, n in sorted(counts.items()))
    return f"fixed {len(fixed)} finding(s): {listed}"


def _fixes_offered(findings: Sequence[Finding], *, unsafe: bool) -> str:
    """What `--fix` (or `--unsafe-fixes`) would put in, as the end of the summary line."""
    from skillwright.rules.fixes import fixable

    safe = sum(fixable(f, unsafe=False) for f in findings)
    risky = sum(fixable(f, unsafe=True) for f in findings) - safe
    parts = []
    if safe:
        parts.append(f"{safe} fixable with --fix")
    if risky and not unsafe:
        parts.append(f"{risky} more with --fix --unsafe-fixes")
    return f"; {', '.join(parts)}" if parts else ""


@click.command("rules")
@click.argument("code", required=False)
@click.option("--json", "as_json", is_flag=True, help="Print the rules as JSON.")
def rules(code: str | None, as_json: bool) -> None:
    """List every rule (code, name, stage, severity, fix), or explain the rule CODE."""
    import json

    from skillwright.console import out_console
    from skillwright.errors import InvalidArgumentError
    from skillwright.rules.registry import UnknownRuleError, all_rules, get

    console = out_console()
    if code is not None:
        try:
            rule = get(code)
        except UnknownRuleError:
            raise InvalidArgumentError(
                f"{code}: no rule has that code or name; `skillwright rules` lists them"
            ) from None
        console.print(rule.explain(), highlight=False, markup=False, soft_wrap=True)
        return
    listed = all_rules()
    if as_json:
        rows = [
            {
                "code": r.code,
                "name": r.name,
                "group": r.group,
                "stage": r.stage,
                "severity": r.severity,
                "fix": r.safety,
                "summary": r.summary,
            }
            for r in listed
        ]
        console.print_json(json.dumps(rows))
        return
    for rule in listed:
        fix = f"fix: {rule.safety}" if rule.safety else "no fix"
        console.print(
            f"{rule.code} {rule.name:<34} {rule.stage:<10} {rule.severity:<7} {fix:<11} "
            f"{rule.summary}",
            highlight=False,
            markup=False,
            soft_wrap=True,
        )
