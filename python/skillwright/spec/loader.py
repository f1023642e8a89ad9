"""Reading skill specifications from JSON (the reference project's format) or YAML.

Both shapes are accepted in either syntax: the reference form
``{"skill": {"name", "description", "skill_interface", "states": [{"name", "action"}]}}``
and the hand-written form without the ``skill`` wrapper and with ``states`` as a mapping
from state name to behaviour text.
"""

from __future__ import annotations

import json
import keyword
from pathlib import Path
from typing import Any

from skillwright.errors import InputFileError, InputFileNotFoundError, SpecError
from skillwright.spec.model import PACKML_STATES, SKILL_INTERFACES, SkillSpec

__all__ = ["load_spec", "parse_spec"]

_FIELDS = ("name", "description", "skill_interface", "states")
_INTERFACE_ALIASES = {
    "rest": "REST",
    "opc_ua": "OPC_UA",
    "opcua": "OPC_UA",
    "opc ua": "OPC_UA",
    "opc-ua": "OPC_UA",
    "mqtt": "MQTT",
}


def _fail(where: str, message: str) -> SpecError:
    return SpecError(f"{where}: {message}")


def _states(raw: Any, where: str) -> dict[str, str]:
    pairs: list[tuple[Any, Any, str]] = []
    if isinstance(raw, dict):
        pairs = [(k, v, f"states.{k}") for k, v in raw.items()]
    elif isinstance(raw, list):
        for index, item in enumerate(raw):
            label = f"states[{index}]"
            if not isinstance(item, dict) or set(item) - {"name", "action"} or "name" not in item:
                raise _fail(
                    where,
                    f"{label} must be an object with 'name' and 'action', got {json.dumps(item)}",
                )
            pairs.append((item["name"], item.get("action"), f"{label} ({item['name']})"))
    else:
        raise _fail(where, "'states' must be a list of {name, action} or a mapping name: action")

    allowed = ", ".join(PACKML_STATES)
    found: dict[str, str] = {}
    for name, action, label in pairs:
        if not isinstance(name, str) or name.strip().lower() not in PACKML_STATES:
            raise _fail(
                where, f"{label}: {name!r} is not a PackML acting state; allowed: {allowed}"
            )
        state = name.strip().lower()
        if state in found:
            raise _fail(where, f"{label}: state '{state}' is given twice")
        if not isinstance(action, str) or not action.strip():
            raise _fail(where, f"{label}: state '{state}' needs a behaviour text ('action')")
        found[state] = " ".join(action.split())
    if "execute" not in found:
        raise _fail(where, "the 'execute' state is required: say what the skill does when it runs")
    return {state: found[state] for state in PACKML_STATES if state in found}


def parse_spec(document: Any, where: str = "specification") -> SkillSpec:
    """Checks a parsed JSON/YAML document and returns the specification.

    ``where`` names the source in error messages (usually the file path).
    """
    if isinstance(document, dict) and set(document) == {"skill"}:
        document = document["skill"]
    if not isinstance(document, dict):
        raise _fail(where, "expected an object with " + ", ".join(_FIELDS))
    unknown = sorted(set(document) - set(_FIELDS))
    if unknown:
        raise _fail(where, f"unknown field(s) {', '.join(unknown)}; allowed: {', '.join(_FIELDS)}")
    missing = [f for f in _FIELDS if f not in document and f != "description"]
    if missing:
        raise _fail(where, f"missing field(s) {', '.join(missing)}")

    name = document["name"]
    if not isinstance(name, str) or not name.isidentifier() or keyword.iskeyword(name):
        raise _fail(
            where,
            f"name {name!r} is not a valid identifier; use letters, digits and '_', "
            "not starting with a digit (e.g. move_forward)",
        )
    description = document.get("description", "")
    if not isinstance(description, str):
        raise _fail(where, "description must be text")
    interface = document["skill_interface"]
    canonical = _INTERFACE_ALIASES.get(str(interface).strip().lower())
    if canonical is None:
        raise _fail(
            where,
            f"skill_interface {interface!r} is not supported; "
            f"allowed: {', '.join(SKILL_INTERFACES)}",
        )
    return SkillSpec(
        name=name,
        description=" ".join(description.split()),
        skill_interface=canonical,
        states=_states(document["states"], where),
    )


def _read_text(path: Path) -> str:
    if not path.exists():
        raise InputFileNotFoundError(f"specification {path}: no such file; check the path")
    if path.is_dir():
        raise InputFileError(f"specification {path}: is a folder; give a .json or .yaml file")
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise SpecError(f"{path}: not UTF-8 text; save the file as UTF-8") from None
    except OSError as error:
        raise InputFileError(f"specification {path}: cannot be read ({error.strerror})") from error


def _parse_json(text: str, path: Path) -> Any:
    try:
        return json.loads(text)
    except json.JSONDecodeError as error:
        raise SpecError(
            f"{path}:{error.lineno}:{error.colno}: JSON syntax error: {error.msg}"
        ) from None


def _parse_yaml(text: str, path: Path) -> Any:
    import yaml

    try:
        return yaml.safe_load(text)
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark
        position = f"{mark.line + 1}:{mark.column + 1}:" if mark is not None else ""
        raise SpecError(f"{path}:{position} YAML syntax error: {error.problem}") from None
    except yaml.YAMLError as error:
        raise SpecError(f"{path}: YAML syntax error: {error}") from None


def load_spec(path: str | Path) -> SkillSpec:
    """Reads and checks the specification at ``path`` (``.json``, ``.yaml`` or ``.yml``).

    Other suffixes are read as JSON when the text starts with ``{``, else as YAML.
    """
    source = Path(path)
    text = _read_text(source)
    suffix = source.suffix.lower()
    if suffix == ".json" or (suffix not in {".yaml", ".yml"} and text.lstrip().startswith("{")):
        document = _parse_json(text, source)
    else:
        document = _parse_yaml(text, source)
    return parse_spec(document, str(source))
