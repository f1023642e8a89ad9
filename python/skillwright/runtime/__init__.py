"""Running a generated skill: a simulated ROS 2 graph on the host, the skill in a sandbox.

Static checks cannot tell whether a skill runs. This package executes a skill's PackML
states against a simulated ROS 2 graph built from the robot's inventory, inside a
sandboxed child process, in virtual time, and reports findings located in the skill file
(the same :class:`~skillwright.validation.model.Finding` shape as the static checks) and
a trace of everything the skill did.

Two processes
-------------
* The **host** (this package, trusted) loads the inventory, builds the graph — replayed
  recordings, default publishers, scripted service and action responders, an optional
  world plug-in — and records the trace. It never imports the stand-ins and never
  executes anything the child sends: the child speaks length-prefixed JSON frames, each
  validated for type and size; a malformed frame is a finding, not a crash.
* The **child** (untrusted) runs from ``skillwright/runtime/child/`` with a minimal
  ``sys.path``: stand-ins of ``rclpy``, ``tf2_ros`` and pySkillUp, message packages
  generated on import from definitions the host sends, and the driver that runs the
  states. See :mod:`skillwright.runtime.sandbox` for its limits.

Virtual, lockstep time
----------------------
Everything in the child that reads or waits on time reads a virtual clock only the host
advances. When the skill blocks until virtual time ``t`` (``time.sleep``, ``spin_once``,
``rate.sleep``, waiting for a future, a transform, an event), the child asks the host to
advance; the host steps every source of events towards ``t`` and returns the deliveries
on the way, each with its time, stopping at most a *lookahead* (scenario setting,
default 20 ms) after the first one; the child runs the callbacks in time order on its
main thread (a single-threaded executor spinning inside the wait), its clock following
each delivery's time, and returns when the skill's condition holds. What the skill does
in reply reaches the graph at most a lookahead later (``lookahead: 0`` is strict
lockstep). Runs are deterministic for a seed and much faster than real time. A state
that never blocks never advances time: its CPU time catches it and the finding names the
line where it was looping.

The host API a world implements against (issue 15)
--------------------------------------------------
A world is any object with the four methods of :class:`~skillwright.runtime.api.WorldPlugin`::

    class MyWorld:
        def attach(self, host: GraphHost) -> None: ...
        def next_event(self) -> float | None: ...   # virtual time of its next publication
        def advance(self, until: float) -> None: ... # step to `until`, publish what is due
        def close(self) -> None: ...

The runtime calls ``attach`` once before each episode (a run has one or two: the normal
one and one with a Stop; a world object must start afresh in ``attach``, or pass
``run_skill`` a factory), then ``advance(t)`` with non-decreasing ``t`` every time
virtual time moves to ``t`` (to the world's own ``next_event()``, to another source's
event, or to the time the skill waits for), and ``close`` at the end of the episode
(also after errors and cancellation). Messages the world publishes during
``advance(t)`` are stamped ``t``.

:class:`~skillwright.runtime.graph.GraphHost` is what the world gets in ``attach``:

``host.now -> float``
    Virtual seconds since the run started.
``host.stamp(t=None) -> {"sec", "nanosec"}``
    The ROS time of virtual time ``t`` (default ``now``): the recording's start time
    (or a fixed epoch for sources without one) plus ``t``; use it for header stamps.
``host.own_topic(topic)``
    The world publishes ``topic`` from now on: replayed and default messages on it stop.
``host.publish(topic, message)``
    Deliver ``message`` (a dict) to the skill's subscribers of ``topic`` at ``now``.
    Missing fields take their defaults; the first messages on each topic are checked,
    and a field the type does not have raises ``ValueError`` naming it.
``host.wants(topic) -> bool``
    Whether a message on ``topic`` would reach anyone now (a subscription of the skill,
    or the last-message slot of a latched topic; every topic with the scenario's
    ``traffic: all``). A world may skip making messages nobody wants; what it computes
    for itself (state, noise, ground truth) must go on the same.
``host.on_publish(topic, callback)``
    ``callback(time, message)`` for every message the skill publishes on ``topic``
    (``message`` a complete dict of the topic's type), called as it happens.
``host.serve_service(name, handler)``
    ``handler(request) -> ServiceReply | dict``: the response dict, or a
    :class:`~skillwright.runtime.api.ServiceReply` with a delay, or none at all (the
    call never completes). Replaces the scripted responder of that service.
``host.serve_action(name, handler)``
    ``handler`` is an :class:`~skillwright.runtime.api.ActionHandler`: ``on_goal(goal)``
    for every goal the skill sends, ``on_cancel(goal) -> bool`` for every cancel
    request. ``goal`` is an :class:`~skillwright.runtime.api.ActionGoal` with
    ``goal.request`` (dict), ``accept()``, ``reject()``, ``feedback(dict)``,
    ``succeed(dict)``, ``abort(dict)``, ``canceled(dict)``, ``status`` and ``active``;
    call them at ``now`` (from ``on_goal``, from ``advance`` or from a
    ``host.call_later`` callback).
``host.call_later(delay, callback)``
    Run ``callback()`` at ``now + delay`` (virtual), in time order with everything else.
``host.message(type_name) -> dict``
    A message of that type (``nav_msgs/msg/Odometry``, ``nav2_msgs/action/NavigateToPose_Goal``)
    with every field at its default: nested dicts, lists, ``{"sec": 0, "nanosec": 0}``.
``host.has_interface(name, kind=None) -> bool``, ``host.type_of(name) -> str | None``
    What the robot's inventory offers.
``host.topics(type_name) -> list[str]``
    The robot's topics of that type (``sensor_msgs/msg/LaserScan``), sorted.
``host.provided(topic) -> bool``
    Whether the scenario's script or the replayed recording publishes ``topic``; a world
    that can make a topic's messages leaves such a topic to them.
``host.report(check, message, severity="error", line=None)``
    A finding of the world (a collision, a limit exceeded); ``line`` defaults to the
    skill line of the skill's most recent publish, call or goal.
``host.record(kind, data)``
    An entry of the world in the run's trace (JSON-serialisable ``data``).
``host.rng``
    A ``random.Random`` seeded from the run's seed, for reproducible noise.

Host-side messages are plain dicts, field name -> value (nested dict, list); ROS time is
``{"sec": int, "nanosec": int}``; byte arrays are lists of ints. Field names and types
come from the inventory's definitions, with the offline type store for the rest.

The built-in :mod:`skillwright.runtime.worlds.kinematic` world (an omnidirectional base
that follows its velocity command, an arm's tool moved where it is sent) is a complete
example of this API. Nav2's and MoveIt's action servers are
:mod:`skillwright.runtime.motion`: a world serves them by implementing its small
:class:`~skillwright.runtime.motion.MotionWorld` interface, as the kinematic and the MuJoCo
world both do.

Running a skill
---------------
:func:`run_skill` (in :mod:`skillwright.runtime.run`) is what ``skillwright run`` and
the pipeline call; it prints nothing, reports progress through an optional callback, is
cancellable, and returns a :class:`~skillwright.runtime.report.RunReport`.
"""
