"""Behaviour validation: the robot simulated in MuJoCo, scenarios, oracles from the model.

The pieces, in the order a validation uses them:

* :mod:`~skillwright.sim.scenario` — the situations a skill is run in (YAML files in
  ``sim/scenarios``, or derived from the capability model).
* :mod:`~skillwright.sim.bindings` — which of the robot's interfaces the world serves, found
  by type in the inventory, and the lidar's geometry from the recording.
* :mod:`~skillwright.sim.world` — :class:`~skillwright.sim.world.MujocoWorld`, a world
  plug-in of the simulated runtime (:mod:`skillwright.runtime`): physics, the base driver
  (:mod:`~skillwright.sim.drive`), sensors, the occupancy map (:mod:`~skillwright.sim.grid`),
  Nav2's and MoveIt's action servers (:mod:`skillwright.runtime.motion`, shared with the
  kinematic world), map saving
  (:mod:`~skillwright.sim.mapfiles`) and ground truth (:mod:`~skillwright.sim.truth`).
* :mod:`~skillwright.sim.oracles` — verdicts derived from the capability model, with its
  OpenMath constraints evaluated by :mod:`~skillwright.sim.openmath`.
* :mod:`~skillwright.sim.validate` — :func:`~skillwright.sim.validate.validate_skill`, what
  ``skillwright validate`` (:mod:`~skillwright.sim.commands`) and the pipeline call; it
  returns a :class:`~skillwright.sim.report.ValidationReport` and draws
  :mod:`~skillwright.sim.plot`'s trajectory plots.

MuJoCo and matplotlib are imported only where a world is built or a plot drawn.
"""
