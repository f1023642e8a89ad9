"""Interface sources: each turns something that knows a robot's interfaces into an inventory.

Every source implements :class:`InterfaceSource` (the paper's ``ControlEntity`` /
``APIDocumentHandling`` idea). Today there is the MCAP / rosbag2 source
(:mod:`skillwright.interfaces.sources.bag`); the live ROS 2 graph and the Cap2Skill
report import produce the same :class:`~skillwright.interfaces.inventory.Inventory`.
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
