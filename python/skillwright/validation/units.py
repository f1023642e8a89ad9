"""Angles in degrees and in radians mixed up (check ``units``).

The paper's capabilities give bearings and headings in degrees (``outDegree [°]``); LaserScan
angles, ``math.atan2`` and every yaw worked out from a quaternion are in radians (REP 103).
``self.out_degree = scan.angle_min + scan.angle_increment * index`` reports 3.07 for an
obstacle at 176 degrees, ``(self.in_degree + self._yaw()) % 360`` adds degrees to radians,
and a quaternion's ``rotation.z`` is no angle at all (for a pure yaw it is sin(yaw / 2)).

Each expression gets the unit it evidently has, with the reason:

- radians: ``angle_min``, ``angle_max`` and ``angle_increment`` of a scan; ``math.atan2``,
  ``atan``, ``asin``, ``acos`` (and numpy's); ``math.radians``; ``x * math.pi / 180``;
- degrees: ``math.degrees``; ``x * 180 / math.pi``;
- an input or output of the capability: the unit its model gives (``°`` or ``rad``);
- a quaternion component: ``.rotation.x`` ... ``.orientation.w``;
- sums and differences take their terms' unit, products the unit of their one factor with a
  unit (``index * scan.angle_increment``), ``abs``, ``min``, ``max``, ``%`` keep it; local
  variables, ``self`` attributes and the values a method returns carry it along.

The skeleton's ``_closest_reading()`` returns a distance in metres beside the bearing. An
angle multiplied by that distance (``scan.angle_increment * self._closest_reading(scan)[0]``,
an index formula fed the helper's range) is no angle at all: the finding says so, and the
fix takes the helper's bearing instead.

A finding needs both sides known: a sum or comparison of degrees and radians, a value in
radians stored in an output in degrees (or the other way round), a quaternion component used
as an angle. The fix converts with ``math.degrees`` or ``math.radians``: into the output's
unit for an output, and into the capability's angle unit for a sum or comparison (when the
capability's angles are all in one unit). Nothing is guessed: an expression without evident
unit (a literal, a reading, ``i * 360 / len(ranges)``) never takes part in a finding.
"""

from __future__ import annotations

import ast
import copy
import dataclasses
import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass

from skillwright.capability.model import Capability
from skillwright.generation.names import snake_case
from skillwright.rules.behaviour import MIXED_ANGLE_UNITS
from skillwright.rules.finding import Finding
from skillwright.validation.facts import SkillFacts
from skillwright.validation.syntax import error_at, self_attribute

__all__ = ["check_angle_units"]

RAD = "radians"
DEG = "degrees"
QUAT = "a quaternion component"
METRES = "metres"
_ANGLES = (RAD, DEG)

_DEGREE_UNITS = frozenset({"°", "deg", "degree", "degrees"})
_RADIAN_UNITS = frozenset({"rad", "radian", "radians"})

_MODULES = frozenset({"math", "np", "numpy"})
_INVERSE_TRIG = frozenset(
    {"atan2", "atan", "asin", "acos", "arctan2", "arctan", "arcsin", "arccos"}
)
_TO_DEGREES = frozenset({"degrees", "rad2deg"})
_TO_RADIANS = frozenset({"radians", "deg2rad"})
_KEEPS_UNIT = frozenset({"abs", "float", "round", "fabs", "remainder", "fmod"})
_SCAN_ANGLES = frozenset({"angle_min", "angle_max", "angle_increment"})
_QUATERNIONS = frozenset({"rotation", "orientation"})


@dataclass(frozen=True)
class _Unit:
    unit: str
    why: str


_HELPER_TUPLES: dict[str, tuple[_Unit | None, ...]] = {
    "_closest_reading": (
        _Unit(METRES, "the distance _closest_reading() returns is in metres"),
        _Unit(RAD, "the bearing _closest_reading() returns is in radians"),
    )
}
"""The units of the elements of the tuples the skeleton's helpers return, by helper."""


@dataclass(frozen=True)
class _Mix:
    """Two terms of different angle units meeting in one operation."""

    node: ast.AST
    parts: tuple[tuple[ast.expr, _Unit], ...]


@dataclass(frozen=True)
class _Scaled:
    """A product of an angle and a distance (``angle_increment * distance``)."""

    node: ast.BinOp
    angle: tuple[ast.expr, _Unit]
    distance: tuple[ast.expr, _Unit]


def check_angle_units(facts: SkillFacts) -> list[Finding]:
    """Findings (check ``units``) for angles in degrees and radians mixed up."""
    declared = _declared(facts.capability)
    if not declared:
        return []
    methods = facts.functions
    returns: dict[str, _Unit] = {}
    attributes: dict[str, _Unit] = {}
    for _ in range(2):  # the second pass sees what helpers return and attributes hold
        returns, attributes = _class_units(methods, declared, returns, attributes)
    findings: list[Finding] = []
    capability_unit = _one_unit(declared)
    for method in methods:
        reader = _Reader(declared, attributes, returns)
        reader.read_block(method.body)
        findings += _findings(facts, method, reader, declared, capability_unit)
    return findings


def _declared(capability: Capability) -> dict[str, _Unit]:
    """The capability's angle inputs and outputs by attribute name."""
    out = {}
    for parameter in (*capability.inputs, *capability.outputs):
        if len(parameter.components) != 1:
            continue
        unit = (parameter.element.unit or "").strip().lower()
        kind = DEG if unit in _DEGREE_UNITS else RAD if unit in _RADIAN_UNITS else None
        if kind is not None:
            why = f"the capability's {parameter.name} is in {parameter.element.unit}"
            out[snake_case(parameter.name)] = _Unit(kind, why)
    return out


def _one_unit(declared: Mapping[str, _Unit]) -> str | None:
    units = {u.unit for u in declared.values()}
    return units.pop() if len(units) == 1 else None


def _class_units(
    methods: Sequence[ast.FunctionDef],
    declared: Mapping[str, _Unit],
    returns: Mapping[str, _Unit],
    attributes: Mapping[str, _Unit],
) -> tuple[dict[str, _Unit], dict[str, _Unit]]:
    """What each method returns and each ``self`` attribute holds, where all agree."""
    returned: dict[str, list[_Unit | None]] = {}
    held: dict[str, list[_Unit | None]] = {}
    for method in methods:
        reader = _Reader(declared, attributes, returns)
        reader.read_block(method.body)
        returned[method.name] = reader.returned
        for name, units in reader.stored.items():
            held.setdefault(name, []).extend(units)
    return _agreed(returned, "{}() returns {}"), _agreed(held, "self.{} holds {}")


def _agreed(found: Mapping[str, list[_Unit | None]], template: str) -> dict[str, _Unit]:
    out = {}
    for name, units in found.items():
        kinds = {u.unit if u else None for u in units}
        if len(kinds) == 1 and None not in kinds and units[0] is not None:
            out[name] = _Unit(units[0].unit, template.format(name, units[0].unit))
    return out


class _Reader:
    """Walks a method in order, giving each expression its evident unit."""

    def __init__(
        self,
        declared: Mapping[str, _Unit],
        attributes: Mapping[str, _Unit],
        returns: Mapping[str, _Unit],
    ) -> None:
        self.declared = declared
        self.attributes = attributes
        self.returns = returns
        self.names: dict[str, _Unit | None] = {}
        self.returned: list[_Unit | None] = []
        self.stored: dict[str, list[_Unit | None]] = {}
        self.mixes: list[_Mix] = []
        self.scaled: list[_Scaled] = []
        self.stores: list[tuple[ast.stmt, str, ast.expr, _Unit]] = []
        """(statement, output attribute, value, the value's unit) for declared attributes."""
        self._seen: set[int] = set()
        self.tuples: dict[str, tuple[_Unit | None, ...]] = {}
        """Local names holding a helper's tuple whole (``closest = self._closest_reading(
        scan)``), read later by index (``closest[1]``)."""

    def read_block(self, body: list[ast.stmt]) -> None:
        for statement in body:
            self.read(statement)

    def read(self, statement: ast.stmt) -> None:
        if isinstance(statement, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            return
        for expression in _expressions(statement):
            self.unit(expression)
        if isinstance(statement, ast.Assign | ast.AnnAssign) and statement.value is not None:
            targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
            value = self.unit(statement.value)
            for target in targets:
                self._bind(statement, target, statement.value, value)
        elif isinstance(statement, ast.AugAssign):
            value = self.unit(statement.value)
            if isinstance(statement.op, ast.Add | ast.Sub):
                current = self.unit(_loaded(statement.target))
                self._mix(
                    statement, [(_loaded(statement.target), current), (statement.value, value)]
                )
        elif isinstance(statement, ast.Return) and statement.value is not None:
            self.returned.append(self.unit(statement.value))
        elif isinstance(statement, ast.For | ast.With):
            for name in _bound_names(statement):
                self.names[name] = None
        for field in ("body", "orelse", "finalbody"):
            block = getattr(statement, field, None)
            if isinstance(block, list):
                self.read_block([s for s in block if isinstance(s, ast.stmt)])
        for handler in getattr(statement, "handlers", []):
            self.read_block(handler.body)

    def _bind(
        self, statement: ast.stmt, target: ast.expr, value: ast.expr, unit: _Unit | None
    ) -> None:
        if isinstance(target, ast.Name):
            self.names[target.id] = unit
            units = _helper_tuple(value)
            if units is None:
                self.tuples.pop(target.id, None)
            else:
                self.tuples[target.id] = units
        elif (attribute := self_attribute(target)) is not None:
            self.stored.setdefault(attribute, []).append(unit)
            if attribute in self.declared and unit is not None:
                self.stores.append((statement, attribute, value, unit))
        elif isinstance(target, ast.Tuple | ast.List):
            units = _helper_tuple(value) or ()
            for index, element in enumerate(target.elts):
                held = units[index] if index < len(units) else None
                if isinstance(element, ast.Name):
                    self.names[element.id] = held
                elif (attribute := self_attribute(element)) is not None:
                    self.stored.setdefault(attribute, []).append(held)
                    if attribute in self.declared and held is not None:
                        part = ast.Subscript(value=value, slice=ast.Constant(index), ctx=ast.Load())
                        self.stores.append((statement, attribute, part, held))

    def _mix(self, node: ast.AST, parts: list[tuple[ast.expr, _Unit | None]]) -> None:
        known = tuple((e, u) for e, u in parts if u is not None and u.unit != METRES)
        if len({u.unit for _e, u in known}) > 1 and id(node) not in self._seen:
            self._seen.add(id(node))
            self.mixes.append(_Mix(node, known))

    def unit(self, node: ast.expr) -> _Unit | None:
        """The evident unit of ``node``; records where units meet and disagree."""
        if isinstance(node, ast.Name):
            return self.names.get(node.id)
        if isinstance(node, ast.Attribute):
            return self._attribute(node)
        if isinstance(node, ast.Call):
            return self._call(node)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
            return self.unit(node.operand)
        if isinstance(node, ast.BinOp):
            return self._binary(node)
        if isinstance(node, ast.Compare):
            terms = [node.left, *node.comparators]
            self._mix(node, [(t, self.unit(t)) for t in terms])
            return None
        if isinstance(node, ast.Subscript) and isinstance(node.slice, ast.Constant):
            held = self.tuples.get(node.value.id) if isinstance(node.value, ast.Name) else None
            units = _helper_tuple(node.value) or held
            index = node.slice.value
            if units is not None and isinstance(index, int) and -len(units) <= index < len(units):
                self.unit(node.value)
                return units[index]
        if isinstance(node, ast.IfExp):
            self.unit(node.test)
            body, orelse = self.unit(node.body), self.unit(node.orelse)
            return body if body and orelse and body.unit == orelse.unit else None
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.expr) and not isinstance(child, ast.Lambda):
                self.unit(child)
        return None

    def _attribute(self, node: ast.Attribute) -> _Unit | None:
        if self_attribute(node) is not None:
            return self.declared.get(node.attr) or self.attributes.get(node.attr)
        if node.attr in _SCAN_ANGLES:
            return _Unit(RAD, f"a scan's {node.attr} is in radians")
        holder = node.value
        if (
            node.attr in ("x", "y", "z", "w")
            and isinstance(holder, ast.Attribute)
            and holder.attr in _QUATERNIONS
        ):
            return _Unit(QUAT, f"{ast.unparse(node)} is {QUAT}, not an angle")
        self.unit(holder)
        return None

    def _call(self, node: ast.Call) -> _Unit | None:
        arguments = [self.unit(a) for a in node.args]
        for keyword in node.keywords:
            self.unit(keyword.value)
        function = node.func
        name = _function_name(function)
        if name in _TO_DEGREES:
            return _Unit(DEG, f"{name}() gives degrees")
        if name in _TO_RADIANS or name in _INVERSE_TRIG:
            return _Unit(RAD, f"{name}() gives radians")
        if name in _KEEPS_UNIT and arguments:
            return arguments[0]
        if isinstance(function, ast.Name) and function.id in ("min", "max"):
            pairs = list(zip(node.args, arguments, strict=True))
            self._mix(node, pairs)
            kinds = {u.unit for _a, u in pairs if u is not None}
            return next((u for _a, u in pairs if u is not None), None) if len(kinds) == 1 else None
        if isinstance(function, ast.Attribute) and self_attribute(function) is not None:
            return self.returns.get(function.attr)
        if isinstance(function, ast.Attribute):
            self.unit(function.value)
        return None

    def _binary(self, node: ast.BinOp) -> _Unit | None:
        if isinstance(node.op, ast.Add | ast.Sub):
            left, right = self.unit(node.left), self.unit(node.right)
            self._mix(node, [(node.left, left), (node.right, right)])
            if left and right:
                return left if left.unit == right.unit else None
            return left or right
        if isinstance(node.op, ast.Mod):
            self.unit(node.right)
            return self.unit(node.left)
        if isinstance(node.op, ast.Mult | ast.Div):
            return self._product(node)
        self.unit(node.left)
        self.unit(node.right)
        return None

    def _product(self, node: ast.BinOp) -> _Unit | None:
        above: list[ast.expr] = []
        below: list[ast.expr] = []
        _factors(node, above, below)
        conversion = _conversion(above, below)
        units = [(f, self.unit(f)) for f in above]
        units_below = [u for f in below if (u := self.unit(f)) is not None]
        if conversion is not None:
            return conversion
        angle = next(((f, u) for f, u in units if u is not None and u.unit in _ANGLES), None)
        distance = next(((f, u) for f, u in units if u is not None and u.unit == METRES), None)
        if angle is not None and distance is not None and id(node) not in self._seen:
            self._seen.add(id(node))
            self.scaled.append(_Scaled(node, angle, distance))
            return None
        known = [u for _f, u in units if u is not None]
        if len(known) == 1 and not units_below:
            return known[0]
        return None


def _helper_tuple(node: ast.expr) -> tuple[_Unit | None, ...] | None:
    """The element units of a call of a skeleton helper that returns a tuple."""
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and self_attribute(node.func) is not None
    ):
        return _HELPER_TUPLES.get(node.func.attr)
    return None


def _factors(
    node: ast.expr, above: list[ast.expr], below: list[ast.expr], flip: bool = False
) -> None:
    """The factors of a product and quotient, split into numerator and denominator."""
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult):
        _factors(node.left, above, below, flip)
        _factors(node.right, above, below, flip)
    elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.Div):
        _factors(node.left, above, below, flip)
        _factors(node.right, above, below, not flip)
    else:
        (below if flip else above).append(node)


def _conversion(above: list[ast.expr], below: list[ast.expr]) -> _Unit | None:
    """The unit a product converts into, when it multiplies by 180/pi or pi/180."""

    def has(factors: list[ast.expr], value: float) -> bool:
        return any(
            _number(f) is not None and math.isclose(_number(f) or 0.0, value, rel_tol=1e-3)
            for f in factors
        )

    if (has(above, 180.0) and has(below, math.pi)) or has(above, 180.0 / math.pi):
        return _Unit(DEG, "multiplying by 180/pi gives degrees")
    if (has(above, math.pi) and has(below, 180.0)) or has(above, math.pi / 180.0):
        return _Unit(RAD, "multiplying by pi/180 gives radians")
    return None


def _number(node: ast.expr) -> float | None:
    if (
        isinstance(node, ast.Constant)
        and isinstance(node.value, int | float)
        and not isinstance(node.value, bool)
    ):
        return float(node.value)
    if (
        isinstance(node, ast.Attribute)
        and node.attr == "pi"
        and isinstance(node.value, ast.Name)
        and node.value.id in _MODULES
    ):
        return math.pi
    return None


def _function_name(function: ast.expr) -> str | None:
    if isinstance(function, ast.Attribute) and isinstance(function.value, ast.Name):
        return function.attr if function.value.id in _MODULES else None
    if isinstance(function, ast.Name):
        return function.id
    return None


def _loaded(target: ast.expr) -> ast.expr:
    loaded = copy.copy(target)
    if hasattr(loaded, "ctx"):
        loaded.ctx = ast.Load()
    return loaded


def _expressions(statement: ast.stmt) -> Iterator[ast.expr]:
    """The expressions a statement evaluates itself (not those of the blocks it holds, nor
    the value an assignment binds, which the reader reads once)."""
    if isinstance(statement, ast.Assign | ast.AnnAssign | ast.AugAssign | ast.Return):
        return iter(())
    if isinstance(statement, ast.If | ast.While):
        return iter([statement.test])
    if isinstance(statement, ast.For):
        return iter([statement.iter])
    if isinstance(statement, ast.With):
        return iter([item.context_expr for item in statement.items])
    if isinstance(statement, ast.Expr | ast.Raise):
        return iter([n for n in ast.iter_child_nodes(statement) if isinstance(n, ast.expr)])
    return iter(())


def _bound_names(statement: ast.For | ast.With) -> list[str]:
    holders = (
        [statement.target]
        if isinstance(statement, ast.For)
        else [i.optional_vars for i in statement.items if i.optional_vars is not None]
    )
    return [n.id for h in holders for n in ast.walk(h) if isinstance(n, ast.Name)]


def _findings(
    facts: SkillFacts,
    method: ast.FunctionDef,
    reader: _Reader,
    declared: Mapping[str, _Unit],
    capability_unit: str | None,
) -> list[Finding]:
    """One finding per statement, with the conversions that put its angles right."""
    problems: dict[int, _Problem] = {}

    def at(node: ast.AST) -> _Problem | None:
        statement = node if isinstance(node, ast.stmt) else facts.statement_holding(node, method)
        if statement is None:
            return None
        return problems.setdefault(id(statement), _Problem(statement))

    for scaled in reader.scaled:
        entry = at(scaled.node)
        if entry is None:
            continue
        (angle, angle_unit), (distance, distance_unit) = scaled.angle, scaled.distance
        bearing = _bearing_of(distance)
        message = (
            f"`{ast.unparse(scaled.node)}` multiplies an angle by a distance: "
            f"`{ast.unparse(angle)}` is in {angle_unit.unit} ({angle_unit.why}) and "
            f"`{ast.unparse(distance)}` in metres ({distance_unit.why}), not the index of a "
            "reading"
        )
        if bearing is None:
            entry.messages.append(
                f"{message}; the bearing of the nearest reading is "
                "self._closest_reading(scan)[1], in radians"
            )
            continue
        entry.messages.append(f"{message}; the fix takes the bearing `{ast.unparse(bearing)}`")
        entry.swaps[id(_with_start_angle(method, scaled.node))] = bearing

    for statement, attribute, value, unit in reader.stores:
        wanted = declared[attribute]
        if unit.unit == wanted.unit:
            continue
        entry = at(statement)
        if entry is None:
            continue
        if unit.unit == METRES:
            entry.messages.append(
                f"self.{attribute} is an angle in {wanted.unit} ({wanted.why}), but "
                f"`{ast.unparse(value)}` is a distance in metres ({unit.why})"
            )
            continue
        if unit.unit == QUAT:
            entry.messages.append(
                f"self.{attribute} is an angle in {wanted.unit} ({wanted.why}), but "
                f"`{ast.unparse(value)}` is {QUAT}, not an angle (for a turn about z, z is "
                "sin(yaw/2) and w cos(yaw/2)); the yaw is "
                "math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))"
            )
            continue
        converter = _converter(wanted.unit)
        entry.messages.append(
            f"self.{attribute} is in {wanted.unit} ({wanted.why}), but `{ast.unparse(value)}` "
            f"is in {unit.unit} ({unit.why}); the fix converts it with math.{converter}"
        )
        entry.wraps[id(value)] = converter
    for problem in problems.values():
        problem.replacement = _unpacked_again(problem.statement, declared)
    for mix in reader.mixes:
        entry = at(mix.node)
        if entry is None:
            continue
        described = "; ".join(f"`{ast.unparse(e)}` is in {u.unit} ({u.why})" for e, u in mix.parts)
        if any(u.unit == QUAT for _e, u in mix.parts):
            entry.messages.append(
                f"`{ast.unparse(mix.node)}` treats {QUAT} as an angle: {described}. For a "
                "turn about z, z is sin(yaw/2) and w cos(yaw/2); the yaw is "
                "math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))"
            )
            continue
        message = f"`{ast.unparse(mix.node)}` mixes degrees and radians: {described}"
        if capability_unit is not None:
            converter = _converter(capability_unit)
            for term, unit in mix.parts:
                if unit.unit != capability_unit:
                    entry.wraps[id(term)] = converter
            message += (
                f"; the capability's angles are in {capability_unit}, so the fix converts the "
                f"others with math.{converter}"
            )
        else:
            message += "; convert one side with math.degrees or math.radians"
        entry.messages.append(message)
    return [_finding(problem) for problem in problems.values()]


def _bearing_of(distance: ast.expr) -> ast.expr | None:
    """``self._closest_reading(x)[1]`` for ``distance`` = ``self._closest_reading(x)[0]``."""
    if (
        isinstance(distance, ast.Subscript)
        and isinstance(distance.slice, ast.Constant)
        and distance.slice.value == 0
        and _helper_tuple(distance.value) is not None
    ):
        return ast.Subscript(value=distance.value, slice=ast.Constant(1), ctx=ast.Load())
    return None


def _with_start_angle(method: ast.FunctionDef, product: ast.BinOp) -> ast.expr:
    """``product`` or, when it is a term of ``scan.angle_min + product``, that sum: the
    index formula whole, which the bearing replaces."""
    for node in ast.walk(method):
        if (
            isinstance(node, ast.BinOp)
            and isinstance(node.op, ast.Add)
            and product in (node.left, node.right)
        ):
            other = node.right if node.left is product else node.left
            if isinstance(other, ast.Attribute) and other.attr == "angle_min":
                return node
    return product


def _unpacked_again(statement: ast.stmt, declared: Mapping[str, _Unit]) -> str | None:
    """For ``self.out_degree, self.out_distance = self._closest_reading(scan)`` (the
    helper's distance and bearing unpacked in the wrong order, or the bearing kept in
    radians for an output in degrees): the statements that put the bearing, converted, into
    the one angle output and the distance into the other target. None for anything else."""
    if not (
        isinstance(statement, ast.Assign)
        and len(statement.targets) == 1
        and isinstance(statement.targets[0], ast.Tuple | ast.List)
    ):
        return None
    units = _helper_tuple(statement.value)
    targets = statement.targets[0].elts
    if units is None or len(units) != len(targets) or len(targets) != 2:
        return None
    angles = [t for t in targets if self_attribute(t) in declared]
    bearing = next((i for i, u in enumerate(units) if u is not None and u.unit == RAD), None)
    if len(angles) != 1 or bearing is None:
        return None
    angle = angles[0]
    other = next(t for t in targets if t is not angle)
    wanted = declared[str(self_attribute(angle))].unit
    local = "bearing"
    placed: list[ast.expr] = [other, other]
    placed[bearing] = angle if wanted == RAD else ast.Name(id=local, ctx=ast.Store())
    unpack = ast.Assign(
        targets=[ast.Tuple(elts=placed, ctx=ast.Store())], value=statement.value, lineno=0
    )
    lines = [ast.unparse(unpack)]
    if wanted != RAD:
        lines.append(f"{ast.unparse(angle)} = math.{_converter(wanted)}({local})")
    return "\n".join(lines)


def _converter(unit: str) -> str:
    return "degrees" if unit == DEG else "radians"


@dataclass
class _Problem:
    """What is wrong with one statement, and the changes that fix it."""

    statement: ast.stmt
    messages: list[str] = dataclasses.field(default_factory=list)
    wraps: dict[int, str] = dataclasses.field(default_factory=dict)
    """Terms (by node id) to put in ``math.<converter>(...)``."""
    swaps: dict[int, ast.expr] = dataclasses.field(default_factory=dict)
    """Terms (by node id) to replace by another expression."""
    replacement: str | None = None
    """The statements that replace the statement whole, where the changes are no terms'."""


def _finding(problem: _Problem) -> Finding:
    replacement = problem.replacement
    changes = problem.wraps.keys() | problem.swaps.keys()
    if changes and len(changes) == sum(1 for n in ast.walk(problem.statement) if id(n) in changes):
        replacement = ast.unparse(_converted(problem))
    return error_at(MIXED_ANGLE_UNITS, problem.statement, "; ".join(problem.messages), replacement)


def _converted(problem: _Problem) -> ast.stmt:
    """A copy of the statement with each term of ``wraps`` in ``math.<converter>(...)`` and
    each of ``swaps`` replaced (then wrapped when both name it)."""
    memo: dict[int, object] = {}
    converted = copy.deepcopy(problem.statement, memo)
    marked = {id(memo[key]): converter for key, converter in problem.wraps.items() if key in memo}
    swapped = {id(memo[key]): new for key, new in problem.swaps.items() if key in memo}

    class _Wrap(ast.NodeTransformer):
        def visit(self, node: ast.AST) -> ast.AST:
            converter = marked.get(id(node))
            new = swapped.get(id(node))
            node = copy.deepcopy(new) if new is not None else self.generic_visit(node)
            if converter is None or not isinstance(node, ast.expr):
                return node
            function = ast.Attribute(
                value=ast.Name(id="math", ctx=ast.Load()), attr=converter, ctx=ast.Load()
            )
            return ast.Call(func=function, args=[node], keywords=[])

    wrapped = _Wrap().visit(converted)
    assert isinstance(wrapped, ast.stmt)
    return ast.fix_missing_locations(wrapped)
