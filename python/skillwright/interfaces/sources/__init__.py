"""Interface sources: each turns something that knows a robot's interfaces into an inventory.

Every source implements :class:`InterfaceSource` (the paper's ``ControlEntity`` /
``APIDocumentHandling`` idea) and produces the same
:class:`~skillwright.interfaces.inventory.Inventory`: MCAP files and rosbag2 folders
(:mod:`~skillwright.interfaces.sources.bag`), the reference tool's JSON reports, which
can also be written back (:mod:`~skillwright.interfaces.sources.report`), and the live
ROS 2 graph (:mod:`~skillwright.interfaces.sources.live`, through the thin
:mod:`~skillwright.interfaces.sources.rclpy_graph`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import TYPE_CHECKING, ClassVar

if TYPE_CHECKING:
    from skillwright.interfaces.inventory import Inventory

__all__ = ["InterfaceSource"]


class InterfaceSource(ABC):
    """Something that can list a resource's ROS 2 interfaces."""

    kind: ClassVar[str]
    """The :attr:`Source.kind <skillwright.interfaces.inventory.Source.kind>` it records."""

    @abstractmethod
    def discover(self) -> Inventory:
        """Reads the source and returns its inventory; raises ``SkillwrightError`` subclasses."""
