"""Stand-in of ``rclpy.node``: a node on the simulated graph.

Every publisher, subscription, client and timer is announced to the host, which checks
it against the robot's interfaces and records it in the trace. Publishing checks the
message's class as rclpy does; subscriptions, responses and timers are delivered by the
executor while the skill waits.
"""

from __future__ import annotations

import re

from _skillwright_child.core import core, quiet

from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.clock import Clock, ROSClock
from rclpy.exceptions import (
    InvalidServiceNameException,
    InvalidTopicNameException,
    NotInitializedException,
    ParameterAlreadyDeclaredException,
    ParameterNotDeclaredException,
)
from rclpy.logging import RcutilsLogger
from rclpy.parameter import Parameter
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    describe,
    profile_of,
    qos_profile_services_default,
)
from rclpy.task import Future
from rclpy.timer import Rate, Timer
from rclpy.topic_endpoint_info import TopicEndpointInfo, TopicEndpointTypeEnum

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any

_NAME_TOKEN = re.compile(r"^[A-Za-z_~{}][A-Za-z0-9_/{}~]*$")


def expand_name(name: str, node_name: str, namespace: str, kind: str = "topic") -> str:
    """``cmd_vel`` -> ``/cmd_vel``, ``~/x`` -> ``/<node>/x``; invalid names raise as rclpy."""
    error = InvalidTopicNameException if kind == "topic" else InvalidServiceNameException
    if not isinstance(name, str):
        raise TypeError(f"{kind} name must be a str, not {type(name).__name__}")
    stripped = name.lstrip("/")
    if not name or not _NAME_TOKEN.match(stripped or "_") or "//" in name or name.endswith("/"):
        raise error(
            name,
            "must not be empty, contain '//' or end with '/', and use only "
            "letters, digits, '_', '/' and '~'",
        )
    if name.startswith("~"):
        base = namespace.rstrip("/") + "/" + node_name
        return base + name[1:]
    if name.startswith("/"):
        return name
    return namespace.rstrip("/") + "/" + name


def _type_name(msg_type: Any, what: str) -> str:
    type_name = getattr(msg_type, "_type_name", None)
    if not isinstance(msg_type, type) or not type_name:
        raise TypeError(
            f"{what} must be a ROS 2 {what.split(maxsplit=1)[0]} class such as "
            f"geometry_msgs.msg.Twist, not {msg_type!r}"
        )
    return type_name


class Publisher:
    """Publishes messages of one type on one topic."""

    def __init__(self, node: Node, msg_type: type, topic: str, qos: QoSProfile) -> None:
        c = core()
        self.msg_type = msg_type
        self.topic = topic
        self.qos_profile = qos
        self._id = c.new_id()
        self._node = node
        self._type_name = _type_name(msg_type, "msg_type")
        c.handles[self._id] = self
        c.notify(
            "endpoint",
            id=self._id,
            kind="publisher",
            name=topic,
            type=self._type_name,
            qos=describe(qos),
            line=c.skill_line(),
        )

    @property
    def topic_name(self) -> str:
        return self.topic

    def publish(self, msg: Any) -> None:
        if not isinstance(msg, self.msg_type):
            raise TypeError(f"Expected {self.msg_type}, got {type(msg)}")
        c = core()
        if self._id not in c.handles:
            raise RuntimeError(f"the publisher of {self.topic} was destroyed")
        c.notify("publish", id=self._id, msg=c.data(msg), line=c.skill_line())

    def get_subscription_count(self) -> int:
        return int(core().request("count", what="subscribers", name=self.topic)["count"])

    def assert_liveliness(self) -> None:
        """Nothing to do: the simulated graph's liveliness is automatic."""

    def wait_for_all_acked(self, timeout: object = None) -> bool:
        """True at once: the simulated graph takes every message when it is published."""
        return True

    def _deliver(self, delivery: dict) -> None:
        return None

    def _quiet(self) -> bool:
        return True

    def destroy(self) -> None:
        self._node.destroy_publisher(self)


class Subscription:
    """Calls ``callback`` with every message delivered on ``topic``."""

    def __init__(
        self,
        node: Node,
        msg_type: type,
        topic: str,
        callback: Callable[[Any], object],
        qos: QoSProfile,
    ) -> None:
        c = core()
        if not callable(callback):
            raise TypeError("callback must be callable")
        self.msg_type = msg_type
        self.topic = topic
        self.callback = callback
        self.qos_profile = qos
        self._id = c.new_id()
        self._node = node
        self._type_name = _type_name(msg_type, "msg_type")
        self._quiet_callback: Callable[[], bool] | None = None
        """Set by the runtime's own stand-ins whose callbacks only store."""
        self._quiet_owner: tuple[type, bool] | None = None
        c.handles[self._id] = self
        c.notify(
            "endpoint",
            id=self._id,
            kind="subscription",
            name=topic,
            type=self._type_name,
            qos=describe(qos),
            line=c.skill_line(),
        )

    @property
    def topic_name(self) -> str:
        return self.topic

    def _deliver(self, delivery: dict) -> None:
        self.callback(core().message(self._type_name, delivery["data"]))

    def _quiet(self) -> bool:
        if self._quiet_callback is not None:
            return self._quiet_callback()
        # The skill's class may change after the subscription is made (the driver's watch).
        owner = type(getattr(self.callback, "__self__", None))
        if self._quiet_owner is None or self._quiet_owner[0] is not owner:
            self._quiet_owner = (owner, quiet(self.callback))
        return self._quiet_owner[1]

    def destroy(self) -> None:
        self._node.destroy_subscription(self)


class Client:
    """Calls a service; responses complete the futures ``call_async`` returns."""

    def __init__(self, node: Node, srv_type: type, srv_name: str) -> None:
        c = core()
        self.srv_type = srv_type
        self.srv_name = srv_name
        self._id = c.new_id()
        self._node = node
        self._type_name = _type_name(srv_type, "srv_type service")
        self._pending: dict[int, Future] = {}
        self._sequence = 0
        c.handles[self._id] = self
        c.notify(
            "endpoint",
            id=self._id,
            kind="client",
            name=srv_name,
            type=self._type_name,
            qos={},
            line=c.skill_line(),
        )

    def service_is_ready(self) -> bool:
        return bool(core().request("exists", kind="service", name=self.srv_name)["ok"])

    def wait_for_service(self, timeout_sec: float | None = None) -> bool:
        if self.service_is_ready():
            return True
        c = core()
        until = None if timeout_sec is None or timeout_sec < 0 else c.now + timeout_sec
        c.block(until, None, f"wait for service {self.srv_name}")
        return self.service_is_ready()

    def call_async(self, request: Any) -> Future:
        if not isinstance(request, self.srv_type.Request):  # type: ignore[attr-defined]
            raise TypeError(f"Expected {self.srv_type.Request}, got {type(request)}")  # type: ignore[attr-defined]
        c = core()
        if self._id not in c.handles:
            raise RuntimeError(f"the client of {self.srv_name} was destroyed")
        self._sequence += 1
        future = Future()
        self._pending[self._sequence] = future
        c.notify(
            "call", id=self._id, seq=self._sequence, request=c.data(request), line=c.skill_line()
        )
        return future

    def call(self, request: Any, timeout_sec: float | None = None) -> Any:
        future = self.call_async(request)
        c = core()
        until = None if timeout_sec is None else c.now + timeout_sec
        c.block(until, future.done, f"call {self.srv_name}")
        if not future.done():
            self.remove_pending_request(future)
            return None
        return future.result()

    def remove_pending_request(self, future: Future) -> None:
        for sequence, pending in list(self._pending.items()):
            if pending is future:
                del self._pending[sequence]

    def _deliver(self, delivery: dict) -> None:
        future = self._pending.pop(int(delivery["seq"]), None)
        if future is not None and not future.done():
            future.set_result(core().message(self._type_name + "_Response", delivery["data"]))

    def _quiet(self) -> bool:
        return not any(future._has_callbacks() for future in self._pending.values())

    def destroy(self) -> None:
        self._node.destroy_client(self)


class Service:
    """A service the skill offers; recorded, but nobody in the simulation calls it."""

    def __init__(self, node: Node, srv_type: type, srv_name: str, callback: Callable) -> None:
        c = core()
        self.srv_type = srv_type
        self.srv_name = srv_name
        self.callback = callback
        self._id = c.new_id()
        self._node = node
        c.handles[self._id] = self
        c.notify(
            "endpoint",
            id=self._id,
            kind="service",
            name=srv_name,
            type=_type_name(srv_type, "srv_type service"),
            qos={},
            line=c.skill_line(),
        )

    def _deliver(self, delivery: dict) -> None:
        return None

    def _quiet(self) -> bool:
        return True

    def destroy(self) -> None:
        self._node.destroy_service(self)


class Node:
    """A ROS 2 node of the skill."""

    PARAM_REL_TOL = 1e-6

    def __init__(
        self,
        node_name: str,
        *,
        context: object = None,
        cli_args: object = None,
        namespace: str | None = None,
        use_global_arguments: bool = True,
        enable_rosout: bool = True,
        start_parameter_services: bool = True,
        parameter_overrides: list[Parameter] | None = None,
        allow_undeclared_parameters: bool = False,
        automatically_declare_parameters_from_overrides: bool = False,
        enable_logger_service: bool = False,
    ) -> None:
        import rclpy

        if not rclpy.ok():
            raise NotInitializedException("cannot create node")
        if not isinstance(node_name, str) or not re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", node_name):
            raise ValueError(
                f"Invalid node name: {node_name!r}: node names may contain only letters, "
                "digits and underscores, and must not start with a digit"
            )
        self._name = node_name
        ns = namespace or "/"
        self._namespace = ns if ns.startswith("/") else "/" + ns
        self._logger = RcutilsLogger(node_name)
        self._clock = ROSClock()
        self._parameters: dict[str, Parameter] = {}
        self._overrides = {p.name: p for p in parameter_overrides or []}
        self._allow_undeclared = allow_undeclared_parameters
        self._handles: list[Any] = []
        self._timers: list[Timer] = []
        self._default_callback_group = MutuallyExclusiveCallbackGroup()
        self._destroyed = False
        core().notify("node", name=node_name, namespace=self._namespace, line=core().skill_line())

    # --- identity ------------------------------------------------------------------

    def get_name(self) -> str:
        return self._name

    def get_namespace(self) -> str:
        return self._namespace

    def get_fully_qualified_name(self) -> str:
        return self._namespace.rstrip("/") + "/" + self._name

    def get_logger(self) -> RcutilsLogger:
        return self._logger

    def get_clock(self) -> Clock:
        return self._clock

    @property
    def executor(self) -> object:
        return None

    @property
    def default_callback_group(self) -> MutuallyExclusiveCallbackGroup:
        """The group of every callback not given one (rclpy's default: mutually exclusive)."""
        return self._default_callback_group

    @property
    def publishers(self) -> list[Publisher]:
        return [h for h in self._handles if isinstance(h, Publisher)]

    @property
    def subscriptions(self) -> list[Subscription]:
        return [h for h in self._handles if isinstance(h, Subscription)]

    @property
    def clients(self) -> list[Client]:
        return [h for h in self._handles if isinstance(h, Client)]

    @property
    def services(self) -> list[Service]:
        return [h for h in self._handles if isinstance(h, Service)]

    @property
    def timers(self) -> list[Timer]:
        return list(self._timers)

    def _check_alive(self) -> None:
        if self._destroyed:
            raise RuntimeError(f"node {self._name} was destroyed")

    def _expand(self, name: str, kind: str = "topic") -> str:
        return expand_name(name, self._name, self._namespace, kind)

    # --- entities ------------------------------------------------------------------

    def create_publisher(
        self,
        msg_type: type,
        topic: str,
        qos_profile: QoSProfile | int,
        *,
        callback_group: object = None,
        event_callbacks: object = None,
        qos_overriding_options: object = None,
        publisher_class: object = None,
    ) -> Publisher:
        self._check_alive()
        publisher = Publisher(self, msg_type, self._expand(topic), profile_of(qos_profile))
        self._handles.append(publisher)
        return publisher

    def create_subscription(
        self,
        msg_type: type,
        topic: str,
        callback: Callable[[Any], object],
        qos_profile: QoSProfile | int,
        *,
        callback_group: object = None,
        event_callbacks: object = None,
        qos_overriding_options: object = None,
        raw: bool = False,
    ) -> Subscription:
        self._check_alive()
        subscription = Subscription(
            self, msg_type, self._expand(topic), callback, profile_of(qos_profile)
        )
        self._handles.append(subscription)
        return subscription

    def create_client(
        self,
        srv_type: type,
        srv_name: str,
        *,
        qos_profile: QoSProfile = qos_profile_services_default,
        callback_group: object = None,
    ) -> Client:
        self._check_alive()
        client = Client(self, srv_type, self._expand(srv_name, "service"))
        self._handles.append(client)
        return client

    def create_service(
        self,
        srv_type: type,
        srv_name: str,
        callback: Callable,
        *,
        qos_profile: QoSProfile = qos_profile_services_default,
        callback_group: object = None,
    ) -> Service:
        self._check_alive()
        service = Service(self, srv_type, self._expand(srv_name, "service"), callback)
        self._handles.append(service)
        return service

    def create_timer(
        self,
        timer_period_sec: float,
        callback: Callable[[], object] | None,
        callback_group: object = None,
        clock: Clock | None = None,
        autostart: bool = True,
    ) -> Timer:
        self._check_alive()
        timer = Timer(callback, timer_period_sec, autostart)
        self._timers.append(timer)
        return timer

    def create_rate(self, frequency: float, clock: Clock | None = None) -> Rate:
        self._check_alive()
        return Rate(frequency)

    def _destroy(self, handle: Any) -> bool:
        c = core()
        if handle in self._handles:
            self._handles.remove(handle)
        if c.handles.pop(handle._id, None) is None:
            return False
        c.notify("destroy", id=handle._id, line=c.skill_line())
        return True

    def destroy_publisher(self, publisher: Publisher) -> bool:
        return self._destroy(publisher)

    def destroy_subscription(self, subscription: Subscription) -> bool:
        return self._destroy(subscription)

    def destroy_client(self, client: Client) -> bool:
        return self._destroy(client)

    def destroy_service(self, service: Service) -> bool:
        return self._destroy(service)

    def destroy_timer(self, timer: Timer) -> bool:
        if timer in self._timers:
            self._timers.remove(timer)
        timer.destroy()
        return True

    def destroy_rate(self, rate: Rate) -> bool:
        rate.destroy()
        return True

    def destroy_node(self) -> None:
        for handle in list(self._handles):
            self._destroy(handle)
        for timer in list(self._timers):
            self.destroy_timer(timer)
        self._destroyed = True

    # --- graph ---------------------------------------------------------------------

    def count_publishers(self, topic_name: str) -> int:
        reply = core().request("count", what="publishers", name=self._expand(topic_name))
        return int(reply["count"])

    def count_subscribers(self, topic_name: str) -> int:
        reply = core().request("count", what="subscribers", name=self._expand(topic_name))
        return int(reply["count"])

    def get_topic_names_and_types(self, no_demangle: bool = False) -> list[tuple[str, list[str]]]:
        reply = core().request("graph", kind="topic")
        return [(name, list(types)) for name, types in reply["names"]]

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        reply = core().request("graph", kind="service")
        return [(name, list(types)) for name, types in reply["names"]]

    def get_node_names(self) -> list[str]:
        return [self._name]

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        return [(self._name, self._namespace)]

    def get_publishers_info_by_topic(
        self, topic_name: str, no_mangle: bool = False
    ) -> list[TopicEndpointInfo]:
        return self._endpoints_info(topic_name, no_mangle, Publisher)

    def get_subscriptions_info_by_topic(
        self, topic_name: str, no_mangle: bool = False
    ) -> list[TopicEndpointInfo]:
        return self._endpoints_info(topic_name, no_mangle, Subscription)

    def _endpoints_info(
        self, topic_name: str, no_mangle: bool, kind: type[Publisher | Subscription]
    ) -> list[TopicEndpointInfo]:
        """The skill's own endpoints of the topic (of every node it made), then the robot's,
        whose node discovery does not name (rmw's ``_NODE_NAME_UNKNOWN_``) and whose history
        DDS does not share."""
        c = core()
        name = topic_name if no_mangle else self._expand(topic_name)
        endpoint_type = (
            TopicEndpointTypeEnum.PUBLISHER
            if kind is Publisher
            else TopicEndpointTypeEnum.SUBSCRIPTION
        )
        infos = [
            TopicEndpointInfo(
                node_name=handle._node.get_name(),
                node_namespace=handle._node.get_namespace(),
                topic_type=handle._type_name,
                endpoint_type=endpoint_type,
                endpoint_gid=[(handle._id >> (8 * i)) & 0xFF for i in range(16)],
                qos_profile=handle.qos_profile,
            )
            for handle in c.handles.values()
            if isinstance(handle, kind) and handle.topic == name
        ]
        what = "publishers" if kind is Publisher else "subscribers"
        for entry in c.request("endpoints", what=what, name=name)["endpoints"]:
            qos = QoSProfile(
                history=HistoryPolicy.UNKNOWN,
                reliability={
                    "reliable": ReliabilityPolicy.RELIABLE,
                    "best_effort": ReliabilityPolicy.BEST_EFFORT,
                }.get(entry["reliability"], ReliabilityPolicy.UNKNOWN),
                durability={
                    "volatile": DurabilityPolicy.VOLATILE,
                    "transient_local": DurabilityPolicy.TRANSIENT_LOCAL,
                }.get(entry["durability"], DurabilityPolicy.UNKNOWN),
            )
            infos.append(
                TopicEndpointInfo(
                    node_name="_NODE_NAME_UNKNOWN_",
                    node_namespace="_NODE_NAMESPACE_UNKNOWN_",
                    topic_type=entry["type"],
                    endpoint_type=endpoint_type,
                    qos_profile=qos,
                )
            )
        return infos

    # --- parameters ----------------------------------------------------------------

    def declare_parameter(
        self,
        name: str,
        value: object = None,
        descriptor: object = None,
        ignore_override: bool = False,
    ) -> Parameter:
        if name in self._parameters:
            raise ParameterAlreadyDeclaredException([name])
        if name in self._overrides and not ignore_override:
            value = self._overrides[name].value
        parameter = Parameter(name, value=value)
        self._parameters[name] = parameter
        return parameter

    def declare_parameters(
        self, namespace: str, parameters: list[tuple], ignore_override: bool = False
    ) -> list[Parameter]:
        declared = []
        for entry in parameters:
            name = f"{namespace}.{entry[0]}" if namespace else entry[0]
            value = entry[1] if len(entry) > 1 else None
            declared.append(self.declare_parameter(name, value, None, ignore_override))
        return declared

    def has_parameter(self, name: str) -> bool:
        return name in self._parameters

    def undeclare_parameter(self, name: str) -> None:
        if name not in self._parameters:
            raise ParameterNotDeclaredException(name)
        del self._parameters[name]

    def get_parameter(self, name: str) -> Parameter:
        if name in self._parameters:
            return self._parameters[name]
        if self._allow_undeclared:
            return Parameter(name, Parameter.Type.NOT_SET, None)
        raise ParameterNotDeclaredException(name)

    def get_parameter_or(self, name: str, alternative_value: Parameter | None = None) -> Parameter:
        if alternative_value is None:
            alternative_value = Parameter(name, Parameter.Type.NOT_SET)
        return self._parameters.get(name, alternative_value)

    def get_parameters(self, names: list[str]) -> list[Parameter]:
        return [self.get_parameter(name) for name in names]

    def get_parameters_by_prefix(self, prefix: str) -> dict[str, Parameter]:
        """The parameters under ``prefix.``, by their names without it (all without one)."""
        start = f"{prefix}." if prefix else ""
        return {
            name[len(start) :]: parameter
            for name, parameter in self._parameters.items()
            if name.startswith(start)
        }

    def set_parameters(self, parameter_list: list[Parameter]) -> list[object]:
        from types import SimpleNamespace

        results = []
        for parameter in parameter_list:
            if parameter.name not in self._parameters and not self._allow_undeclared:
                raise ParameterNotDeclaredException(parameter.name)
            self._parameters[parameter.name] = parameter
            results.append(SimpleNamespace(successful=True, reason=""))
        return results

    def add_on_set_parameters_callback(self, callback: Callable) -> Callable:
        return callback

    def remove_on_set_parameters_callback(self, callback: Callable) -> None:
        return None
