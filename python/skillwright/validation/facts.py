"""What the static checks know of one skill file, worked out once and shared by all of them.

:func:`skillwright.validation.static.check_skill` parses a file once, builds one
:class:`SkillFacts` from it and hands that to every check, which asks it for what it needs:
the tree and its index (the simple statement and the innermost statement holding a node), the
message classes the file imports, the skill class and its ``@skill`` decorator, its methods
and the PackML state methods, the getters of its parameters and outputs and their binding to
the capability, the rclpy and tf2 objects it makes (handles: attribute -> kind, interface and
type), the attributes its callbacks store into and those it keeps the latest messages in, the
expressions that are readings of the robot, and the skeleton helpers' parameters. Each fact is
worked out when a check first asks for it and then kept, so a fact no check of the file needs
costs nothing.

Where the checks once read a fact differently, the facts read it as the API defines it:

- an rclpy handle's type and name are the arguments rclpy's makers take, by position or by
  keyword (``create_publisher(msg_type, topic)``, ``create_subscription(msg_type, topic,
  callback)``, ``create_client(srv_type, srv_name)``, ``ActionClient(node, action_type,
  action_name)``), and the callback of a subscription is the skill's method it hands over
  (``self._on_scan``); an interface name is the name ROS 2 resolves it to (``scan`` in the
  root namespace is ``/scan``);
- an argument of a skeleton helper is the one Python binds to the parameter: by keyword, else
  at its position in the skill's own definition of the helper (the method that runs), else in
  the skeleton's (:mod:`skillwright.generation.helpers`);
- the attribute an input is kept in is the one its getter returns, as pySkillUp reads it and
  the run sets it (:func:`skillwright.runtime.skillinfo.returned_path`);
- a ``@skill_parameter`` or ``@skill_output`` is the decorator however it is reached
  (``skill_parameter(...)`` or ``decorators.skill_parameter(...)``).
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache, cached_property
from typing import Literal

from skillwright.capability.binding import Annotation, Binding, bind
from skillwright.capability.model import Capability
from skillwright.generation.helpers import helper_signature
from skillwright.runtime.skillinfo import decorator_name, returned_path
from skillwright.spec.model import PACKML_STATES, SkillSpec
from skillwright.validation.model import Catalog
from skillwright.validation.syntax import (
    COMPOUND_STATEMENTS,
    called_name,
    keyword_argument,
    self_attribute,
    self_method,
    string_value,
    written_type,
)

__all__ = ["Getter", "Handle", "InterfaceUse", "MadeHandle", "SkillFacts", "is_clock_now"]

_MAKERS: dict[str, str] = {
    "create_publisher": "publisher",
    "create_subscription": "subscription",
    "create_client": "client",
    "create_timer": "timer",
    "create_rate": "rate",
    "ActionClient": "action_client",
    "TransformListener": "tf_listener",
    "Buffer": "tf_buffer",
    "get_logger": "logger",
}
"""The calls that make an rclpy or tf2 object, and the kind of object each makes."""

_INTERFACE_ARGUMENTS: dict[str, tuple[str, tuple[int, str], tuple[int, str]]] = {
    "create_publisher": ("topic", (0, "msg_type"), (1, "topic")),
    "create_subscription": ("topic", (0, "msg_type"), (1, "topic")),
    "create_client": ("service", (0, "srv_type"), (1, "srv_name")),
    "ActionClient": ("action", (1, "action_type"), (2, "action_name")),
}
"""The makers of a handle for one interface: the interface's kind and where the call gives
its type and its name (position, keyword), as rclpy's signatures have them."""

_TF_MESSAGE = "tf2_msgs/msg/TFMessage"
"""What the transform tree carries (``/tf``)."""

_SHARED = (ast.expr_context, ast.operator, ast.boolop, ast.unaryop, ast.cmpop)
"""Nodes the parser shares between every place that has them (one ``ast.Load()`` for all
loads): they have no one parent."""

_COMPONENTS = frozenset({"x", "y", "z", "w"})
_READINGS = frozenset({"_yaw", "_closest_reading"})
"""The skeleton's helpers that give a reading of the robot."""

_SKILL_DECORATORS = frozenset({"skill_parameter", "skill_output"})


def _argument(call: ast.Call, position: int, keyword: str) -> ast.expr | None:
    if len(call.args) > position:
        return call.args[position]
    return next((k.value for k in call.keywords if k.arg == keyword), None)


@dataclass(frozen=True)
class MadeHandle:
    """A call that makes an rclpy or tf2 object (:data:`_MAKERS`), anywhere in the file."""

    call: ast.Call
    maker: str
    """The call's name: ``create_publisher``, ``ActionClient`` ..."""
    type_name: str | None
    """The interface's ROS type (``geometry_msgs/msg/Twist``), through the file's imports."""

    @property
    def kind(self) -> str:
        """The kind of object: ``publisher``, ``action_client``, ``tf_listener`` ..."""
        return _MAKERS[self.maker]

    @property
    def interface_kind(self) -> str | None:
        """``topic``, ``service`` or ``action`` for a handle of one interface."""
        arguments = _INTERFACE_ARGUMENTS.get(self.maker)
        return arguments[0] if arguments is not None else None

    @property
    def type_argument(self) -> ast.expr | None:
        """The interface's type as the call gives it."""
        arguments = _INTERFACE_ARGUMENTS.get(self.maker)
        return None if arguments is None else _argument(self.call, *arguments[1])

    @property
    def name_argument(self) -> ast.expr | None:
        """The interface's name as the call gives it."""
        arguments = _INTERFACE_ARGUMENTS.get(self.maker)
        return None if arguments is None else _argument(self.call, *arguments[2])

    @property
    def type_written(self) -> str | None:
        """The type's class as the skill names it (``Twist``, also for
        ``geometry_msgs.msg.Twist``)."""
        return written_type(self.type_argument)

    @property
    def name(self) -> str | None:
        """The interface's full name (``/scan`` for ``"scan"``) when the call gives it as a
        string literal; ``None`` otherwise."""
        written = self.name_argument
        if not (isinstance(written, ast.Constant) and isinstance(written.value, str)):
            return None
        return written.value if written.value.startswith("/") else f"/{written.value}"

    @property
    def callback(self) -> str | None:
        """The method of the skill a subscription hands its messages to (``_on_scan``)."""
        if self.maker != "create_subscription":
            return None
        given = _argument(self.call, 2, "callback")
        return None if given is None else self_attribute(given)


@dataclass(frozen=True)
class InterfaceUse:
    """An interface of the robot the file uses: one a handle is made for, or the transform
    tree a tf2 ``TransformListener`` subscribes to."""

    name: str
    """Its full name: ``/cmd_vel``."""
    kind: str
    """``topic``, ``service`` or ``action``."""
    type_name: str | None
    """Its ROS type, where the file names one it imports."""
    call: ast.Call
    """The call that makes its handle."""


@dataclass(frozen=True)
class Handle:
    """An rclpy or tf2 object the class keeps: a made handle assigned to a name or to an
    attribute of the skill."""

    target: str
    """Where it is kept, as the code writes it: ``self.cmd_vel_publisher``, ``publisher``."""
    made: MadeHandle

    @property
    def attribute(self) -> str | None:
        """``cmd_vel_publisher`` when the handle is kept on the skill."""
        return self.target.removeprefix("self.") if self.target.startswith("self.") else None


@dataclass(frozen=True)
class Getter:
    """A ``@skill_parameter`` or ``@skill_output`` getter of the class."""

    annotation: Annotation
    decorator: ast.Call
    method: ast.FunctionDef

    @property
    def path(self) -> str | None:
        """What the getter returns of the skill (``x``, ``goal.x``), as the run reads it."""
        return returned_path(self.method)


@dataclass(frozen=True)
class SkillFacts:
    """The facts of one parsed skill file that the static checks read (see the module)."""

    source: str
    tree: ast.Module
    skill: ast.ClassDef | None
    """The class decorated with ``@skill(...)``; ``None`` when the file has none."""
    capability: Capability
    spec: SkillSpec
    catalog: Catalog | None = None
    """The robot's interfaces, for the grounding checks; ``None`` leaves them out."""
    retrieved: tuple[str, ...] = ()
    """The interfaces retrieval chose, for the used-versus-retrieved check."""
    bindings: Mapping[str, str] = field(default_factory=dict)
    """The skill's annotation -> the capability's name, as ``--bind`` says."""
    _walks: dict[int, tuple[ast.AST, ...]] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )

    @classmethod
    def build(
        cls,
        source: str,
        *,
        capability: Capability,
        spec: SkillSpec,
        catalog: Catalog | None = None,
        retrieved: Sequence[str] = (),
        path: str = "skill.py",
        bindings: Mapping[str, str] | None = None,
    ) -> SkillFacts:
        """The facts of ``source``; raises :class:`SyntaxError` when it does not parse."""
        tree = ast.parse(source, filename=path)
        skill = next(
            (
                node
                for node in tree.body
                if isinstance(node, ast.ClassDef) and _skill_decorator(node) is not None
            ),
            None,
        )
        return cls(
            source=source,
            tree=tree,
            skill=skill,
            capability=capability,
            spec=spec,
            catalog=catalog,
            retrieved=tuple(retrieved),
            bindings=dict(bindings or {}),
        )

    # --- the tree --------------------------------------------------------------------

    def walk(self, root: ast.AST) -> tuple[ast.AST, ...]:
        """Every node under ``root`` (itself first), in :func:`ast.walk`'s order; the walk of
        each root is made once."""
        found = self._walks.get(id(root))
        if found is None:
            found = self._walks[id(root)] = tuple(ast.walk(root))
        return found

    def calls(self, root: ast.AST) -> Iterable[ast.Call]:
        """The calls under ``root``, in :func:`ast.walk`'s order."""
        return (node for node in self.walk(root) if isinstance(node, ast.Call))

    @cached_property
    def statement_of(self) -> Mapping[int, ast.stmt]:
        """The innermost simple (not compound) statement of every node inside one, by node
        id."""
        return {
            id(node): statement
            for statement in self.walk(self.tree)
            if isinstance(statement, ast.stmt) and not isinstance(statement, COMPOUND_STATEMENTS)
            for node in self.walk(statement)
        }

    @cached_property
    def _parents(self) -> Mapping[int, ast.AST]:
        return {
            id(child): node
            for node in self.walk(self.tree)
            for child in ast.iter_child_nodes(node)
            if not isinstance(child, _SHARED)
        }

    def parent(self, node: ast.AST) -> ast.AST | None:
        """The node that holds ``node`` directly (``None`` for the module, and for the
        contexts and operators the parser shares)."""
        return self._parents.get(id(node))

    def statement_holding(self, node: ast.AST, root: ast.AST | None = None) -> ast.stmt | None:
        """The innermost statement (not a definition) that holds ``node``, when it lies
        under ``root`` (the whole file by default)."""
        parents = self._parents
        current: ast.AST | None = node
        while current is not None and not (
            isinstance(current, ast.stmt)
            and not isinstance(current, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef)
        ):
            current = parents.get(id(current))
        if current is None or root is None or root is self.tree:
            return current if isinstance(current, ast.stmt) else None
        ancestor: ast.AST | None = current
        while ancestor is not None and ancestor is not root:
            ancestor = parents.get(id(ancestor))
        return current if ancestor is root and isinstance(current, ast.stmt) else None

    @cached_property
    def imports(self) -> Mapping[str, str]:
        """Local name -> ``pkg/msg/Type`` (or ``srv``, ``action``) of the interface classes
        the file imports (``from geometry_msgs.msg import Twist [as Alias]``)."""
        out: dict[str, str] = {}
        for node in self.walk(self.tree):
            if isinstance(node, ast.ImportFrom) and node.module:
                parts = node.module.split(".")
                if len(parts) == 2 and parts[1] in {"msg", "srv", "action"}:
                    for alias in node.names:
                        out[alias.asname or alias.name] = f"{parts[0]}/{parts[1]}/{alias.name}"
        return out

    @cached_property
    def modules(self) -> frozenset[str]:
        """The modules the file imports with ``import`` (their first name: ``os`` for
        ``os.path``)."""
        return frozenset(
            (alias.asname or alias.name).split(".")[0]
            for node in self.tree.body
            if isinstance(node, ast.Import)
            for alias in node.names
        )

    # --- the class ---------------------------------------------------------------------

    @cached_property
    def decorator(self) -> ast.Call | None:
        """The skill class's ``@skill(...)``."""
        return None if self.skill is None else _skill_decorator(self.skill)

    @cached_property
    def nodes(self) -> tuple[ast.AST, ...]:
        """Every node of the skill class (none without one), in :func:`ast.walk`'s order."""
        return () if self.skill is None else self.walk(self.skill)

    @cached_property
    def functions(self) -> tuple[ast.FunctionDef, ...]:
        """The class's methods, in the order it defines them."""
        if self.skill is None:
            return ()
        return tuple(n for n in self.skill.body if isinstance(n, ast.FunctionDef))

    @cached_property
    def definitions(self) -> tuple[ast.FunctionDef | ast.AsyncFunctionDef, ...]:
        """The class's methods, ``async def`` ones too, in the order it defines them."""
        if self.skill is None:
            return ()
        return tuple(
            n for n in self.skill.body if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef)
        )

    @cached_property
    def methods(self) -> Mapping[str, ast.FunctionDef]:
        """The class's methods by name (a name defined twice is its last definition, as
        Python keeps it)."""
        return {method.name: method for method in self.functions}

    @cached_property
    def states(self) -> Mapping[str, ast.FunctionDef]:
        """PackML state -> the method decorated with it (``@execute``)."""
        out: dict[str, ast.FunctionDef] = {}
        for method in self.functions:
            for decorator in method.decorator_list:
                if isinstance(decorator, ast.Name) and decorator.id in PACKML_STATES:
                    out[decorator.id] = method
        return out

    @cached_property
    def getters(self) -> tuple[Getter, ...]:
        """The class's ``@skill_parameter`` and ``@skill_output`` getters, in order."""
        found: list[Getter] = []
        for method in self.functions:
            for decorator in method.decorator_list:
                kind = decorator_name(decorator) if isinstance(decorator, ast.Call) else None
                if kind not in _SKILL_DECORATORS or not isinstance(decorator, ast.Call):
                    continue
                name = string_value(keyword_argument(decorator, "name")) or method.name
                described = string_value(keyword_argument(decorator, "description")) or ""
                direction: Literal["input", "output"] = (
                    "input" if kind == "skill_parameter" else "output"
                )
                annotation = Annotation(name, direction, described, decorator.lineno)
                found.append(Getter(annotation, decorator, method))
        return tuple(found)

    @cached_property
    def binding(self) -> Binding:
        """The getters' annotations bound to the capability's inputs and outputs (by name, by
        meaning, or as :attr:`bindings` says)."""
        return bind([g.annotation for g in self.getters], self.capability, self.bindings)

    @cached_property
    def input_attributes(self) -> Mapping[str, str]:
        """Attribute -> the capability input whose value the skill keeps in it: what the
        getter of each bound ``@skill_parameter`` returns (``target_angular_speed`` for
        inVelocity)."""
        held: dict[str, str] = {}
        for getter in self.getters:
            meant = self.binding.target_of(getter.annotation.name)
            path = getter.path
            if meant is not None and getter.annotation.direction == "input" and path is not None:
                held[path.split(".")[0]] = meant
        return held

    @cached_property
    def parameter_attributes(self) -> frozenset[str]:
        """The attributes pySkillUp sets for each ``@skill_parameter``: the one its getter
        reads (``return self.a``, or the root of ``return self.goal.x``)."""
        return frozenset(
            path.split(".")[0]
            for getter in self.getters
            if getter.annotation.direction == "input" and (path := getter.path) is not None
        )

    @cached_property
    def set_attributes(self) -> frozenset[str]:
        """The names the class body defines and every ``self`` attribute a statement of the
        class sets (an assignment, a ``for`` or ``with`` target)."""
        if self.skill is None:
            return frozenset()
        found: set[str] = set()
        for member in self.skill.body:
            if isinstance(member, ast.FunctionDef | ast.AsyncFunctionDef):
                found.add(member.name)
            elif isinstance(member, ast.Assign):
                found |= {t.id for t in member.targets if isinstance(t, ast.Name)}
            elif isinstance(member, ast.AnnAssign) and isinstance(member.target, ast.Name):
                found.add(member.target.id)
        for node in self.walk(self.skill):
            if isinstance(node, ast.Assign | ast.AnnAssign | ast.AugAssign):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                found |= {
                    name
                    for target in targets
                    for part in self.walk(target)
                    if (name := self_attribute(part)) is not None
                }
            elif isinstance(node, ast.For | ast.With):
                found |= {
                    name
                    for part in self.walk(node.target if isinstance(node, ast.For) else node)
                    if isinstance(part, ast.Attribute)
                    and isinstance(part.ctx, ast.Store)
                    and (name := self_attribute(part)) is not None
                }
        return frozenset(found)

    # --- handles -----------------------------------------------------------------------

    @cached_property
    def made(self) -> tuple[MadeHandle, ...]:
        """Every call in the file that makes an rclpy or tf2 object, in walk order."""
        found = []
        for call in self.calls(self.tree):
            maker = called_name(call)
            if maker not in _MAKERS:
                continue
            arguments = _INTERFACE_ARGUMENTS.get(maker)
            written = None if arguments is None else _argument(call, *arguments[1])
            type_name = None if written is None else self.imports.get(ast.unparse(written))
            found.append(MadeHandle(call, maker, type_name))
        return tuple(found)

    @cached_property
    def interface_uses(self) -> tuple[InterfaceUse, ...]:
        """The interfaces the file's made handles use, in walk order; a handle whose name is
        not a string literal uses none that can be known."""
        found = []
        for made in self.made:
            if made.maker == "TransformListener":
                found.append(InterfaceUse("/tf", "topic", _TF_MESSAGE, made.call))
            elif made.interface_kind is not None and made.name is not None:
                found.append(
                    InterfaceUse(made.name, made.interface_kind, made.type_name, made.call)
                )
        return tuple(found)

    @cached_property
    def handles(self) -> tuple[Handle, ...]:
        """The objects the class makes and keeps (``self.x = self.node.create_publisher(...)``,
        ``client = ActionClient(...)``), each target of the assignment, in walk order."""
        if self.skill is None:
            return ()
        made = {id(m.call): m for m in self.made}
        found = []
        for node in self.walk(self.skill):
            if not isinstance(node, ast.Assign | ast.AnnAssign | ast.AugAssign):
                continue
            handle = made.get(id(node.value))
            if handle is None:
                continue
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            found += [Handle(ast.unparse(target), handle) for target in targets]
        return tuple(found)

    @cached_property
    def kinds(self) -> Mapping[str, str]:
        """Attribute -> the rclpy kind of what it holds, where the code makes it plain: the
        node (``node``), each handle the skill keeps on itself (the last one made wins, as
        it does when the code runs) and each ``self.x = <clock>.now()`` (``time``)."""
        kinds = {"node": "node"}
        if self.skill is None:
            return kinds
        made = {id(h.made.call): h.made.kind for h in self.handles}
        for node in self.walk(self.skill):
            if not isinstance(node, ast.Assign | ast.AnnAssign | ast.AugAssign):
                continue
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            name = self_attribute(targets[0]) if len(targets) == 1 else None
            if name is None or not isinstance(node.value, ast.Call):
                continue
            if id(node.value) in made:
                kinds[name] = made[id(node.value)]
            elif is_clock_now(node.value):
                kinds[name] = "time"
        return kinds

    # --- messages and callbacks --------------------------------------------------------

    @cached_property
    def latest_messages(self) -> Mapping[str, str]:
        """``X_msg`` -> the message class as written, for each ``self.X_msg: <Type> | None``
        the class declares: the skeleton keeps each subscription's latest message there,
        ``None`` until the first one arrives."""
        if self.skill is None:
            return {}
        found: dict[str, str] = {}
        for node in self.walk(self.skill):
            if not isinstance(node, ast.AnnAssign):
                continue
            name = self_attribute(node.target)
            if name is not None and name.endswith("_msg"):
                annotation = node.annotation
                if isinstance(annotation, ast.BinOp):  # Odometry | None
                    annotation = annotation.left
                found.setdefault(name, ast.unparse(annotation))
        return found

    @cached_property
    def callbacks(self) -> frozenset[str]:
        """The methods the class hands over as callbacks: a method of the class passed as an
        argument of a call (``self._on_odom`` to ``create_subscription``, a timer's or a
        goal's callback)."""
        return frozenset(
            name
            for method in self.methods.values()
            for call in self.calls(method)
            for argument in [*call.args, *(k.value for k in call.keywords)]
            if (name := self_attribute(argument)) is not None and name in self.methods
        )

    @cached_property
    def callback_stores(self) -> frozenset[str]:
        """The attributes the callbacks set: what may change while a state waits."""
        return frozenset(
            node.attr
            for name in self.callbacks
            for node in self.walk(self.methods[name])
            if isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Store)
            and self_attribute(node) is not None
        )

    def kept_messages(self, callback: str) -> frozenset[str]:
        """The attributes the method ``callback`` assigns its message parameter to."""
        method = self.methods.get(callback)
        parameters = [] if method is None else method.args.args[1:]
        if method is None or not parameters:
            return frozenset()
        message = parameters[0].arg
        return frozenset(
            attribute
            for node in self.walk(method)
            if isinstance(node, ast.Assign)
            and isinstance(node.value, ast.Name)
            and node.value.id == message
            for target in node.targets
            if (attribute := self_attribute(target)) is not None
        )

    # --- readings ------------------------------------------------------------------------

    @cached_property
    def is_measured(self) -> Callable[[ast.expr], bool]:
        """Whether an expression of the class is, or computes from, a measured number: a
        coordinate or component (``x``, ``y``, ``z``, ``w``) of a field of a latest message,
        a reading of a scan's ``ranges``, the skeleton's ``self._yaw(...)`` or
        ``self._closest_reading(...)``, arithmetic on those, or a name, attribute or method
        of the class that holds or returns one."""
        latest = set(self.latest_messages)
        latest |= self._message_parts(latest)
        measured = self._measured_names(latest)
        return lambda node: _is_measured(node, latest, measured)

    def _message_parts(self, latest: set[str]) -> set[str]:
        """Local names the class assigns a latest message or a part of one to."""
        if self.skill is None:
            return set()
        return {
            node.targets[0].id
            for node in self.walk(self.skill)
            if isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and isinstance(node.targets[0], ast.Name)
            and isinstance(node.value, ast.Attribute)
            and _reads_latest(node.value, latest)
        }

    def _measured_names(self, latest: set[str]) -> set[str]:
        """Local names, ``self.<name>`` attributes and ``self.<method>()`` of the class that
        hold or give a measured number."""
        measured: set[str] = set()
        if self.skill is None:
            return measured
        assignments = [
            n
            for n in self.walk(self.skill)
            if isinstance(n, ast.Assign)
            and len(n.targets) == 1
            and not isinstance(n.value, ast.Lambda)
        ]
        returned = {
            method.name: [
                n.value
                for n in self.walk(method)
                if isinstance(n, ast.Return) and n.value is not None
            ]
            for method in self.functions
        }
        for _ in range(3):  # a name from a name from a reading
            for node in assignments:
                target = node.targets[0]
                key = (
                    target.id
                    if isinstance(target, ast.Name)
                    else f"self.{name}"
                    if (name := self_attribute(target)) is not None
                    else None
                )
                if key is not None and _is_direct(node.value, latest, measured):
                    measured.add(key)
            for method in self.functions:
                values = returned[method.name]
                if values and all(_is_measured(v, latest, measured) for v in values):
                    measured.add(f"self.{method.name}()")
        return measured

    # --- the skeleton's helpers ------------------------------------------------------------

    def helper_argument(self, call: ast.Call, parameter: str) -> ast.expr | None:
        """The argument ``call`` of a helper of the skill passes for ``parameter``: by keyword,
        else at the parameter's position in the skill's own definition of the helper (the
        method that runs), else in the skeleton's."""
        for keyword in call.keywords:
            if keyword.arg == parameter:
                return keyword.value
        name = self_method(call)
        definition = self.methods.get(name) if name is not None else None
        if definition is not None:
            positional = [a.arg for a in definition.args.args if a.arg != "self"]
        else:
            positional = [] if name is None else list(_skeleton_parameters(name))
        if parameter not in positional:
            return None
        position = positional.index(parameter)
        return call.args[position] if position < len(call.args) else None


@cache
def _skeleton_parameters(helper: str) -> tuple[str, ...]:
    """The parameters (without ``self``) the skeleton's ``helper`` takes, read once from
    :mod:`skillwright.generation.helpers`; empty for a name that is none of its helpers."""
    try:
        return tuple(helper_signature(helper).parameters)
    except LookupError:
        return ()


def is_clock_now(node: ast.expr) -> bool:
    """Whether ``node`` is ``<...>.get_clock().now()``, an rclpy Time."""
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "now"
        and isinstance(node.func.value, ast.Call)
        and isinstance(node.func.value.func, ast.Attribute)
        and node.func.value.func.attr == "get_clock"
    )


def _skill_decorator(cls: ast.ClassDef) -> ast.Call | None:
    return next(
        (d for d in cls.decorator_list if isinstance(d, ast.Call) and decorator_name(d) == "skill"),
        None,
    )


def _reads_latest(node: ast.expr, latest: set[str]) -> bool:
    """Whether the attribute chain ``node`` starts at a latest message (``self.odom_msg``)
    or at a name the class assigns a part of one to (``here =
    self.odom_msg.pose.pose.position``)."""
    while isinstance(node, ast.Attribute | ast.Subscript):
        if self_attribute(node) in latest:
            return True
        node = node.value
    return isinstance(node, ast.Name) and node.id in latest


def _is_measured(node: ast.expr, latest: set[str], measured: set[str]) -> bool:
    """Whether ``node`` is, or computes from, a measured number."""
    if isinstance(node, ast.Name):
        return node.id in measured
    if isinstance(node, ast.Attribute):
        name = self_attribute(node)
        if name is not None:
            return f"self.{name}" in measured
        return node.attr in _COMPONENTS and _reads_latest(node, latest)
    if isinstance(node, ast.Subscript):
        holder = node.value
        if isinstance(holder, ast.Call):  # self._closest_reading(scan)[0]
            return _is_measured(holder, latest, measured)
        return (
            isinstance(holder, ast.Attribute)
            and holder.attr == "ranges"
            and _reads_latest(holder, latest)
        )
    if isinstance(node, ast.Call):
        called = self_attribute(node.func)
        if called in _READINGS or f"self.{called}()" in measured:
            return True
        function = node.func
        if (isinstance(function, ast.Name) and function.id in ("abs", "float", "round")) or (
            isinstance(function, ast.Attribute) and ast.unparse(function.value) == "math"
        ):
            return any(_is_measured(a, latest, measured) for a in node.args)
        return False
    if isinstance(node, ast.BinOp):
        return _is_measured(node.left, latest, measured) or _is_measured(
            node.right, latest, measured
        )
    if isinstance(node, ast.UnaryOp):
        return _is_measured(node.operand, latest, measured)
    return False


def _is_direct(node: ast.expr, latest: set[str], measured: set[str]) -> bool:
    """A measured number read from a message itself (not a local holding a message)."""
    if isinstance(node, ast.Attribute) and self_attribute(node) is None:
        chain: ast.expr = node
        while isinstance(chain, ast.Attribute | ast.Subscript):
            if self_attribute(chain) in latest:
                return node.attr in _COMPONENTS
            chain = chain.value
        return False
    return _is_measured(node, latest, measured)
