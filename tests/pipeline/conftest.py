"""Fixtures of the pipeline tests: isolated configuration, a tiny model, a scripted model."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pytest

from tests.conftest import SHIPPED_CAPABILITIES
from tests.fixtures.scripted import MethodScript
from tests.llm.conftest import isolated_config, wordy_gguf, write_models_toml

__all__ = ["SET_VELOCITY", "isolated_config", "wordy_gguf"]

RECORDING = SHIPPED_CAPABILITIES / "recordings" / "mr1"

SET_VELOCITY = {
    "starting": [
        """        self._wait_until(lambda: self.odom_msg is not None, 2.0, "odometry on /odom")
```"""
    ],
    "execute": [
        """        linear = max(-self.LINEAR_VELOCITY_MAX, min(self.LINEAR_VELOCITY_MAX, self.in_linear_velocity))
        angular = max(-self.ANGULAR_VELOCITY_MAX, min(self.ANGULAR_VELOCITY_MAX, self.in_angular_velocity))
        if linear != self.in_linear_velocity or angular != self.in_angular_velocity:
            self.node.get_logger().warning(f"clipped to {linear:.2f} m/s, {angular:.2f} rad/s")
        self.command = Twist()
        self.command.linear.x = linear
        self.command.angular.z = angular
        self.timer = self.node.create_timer(0.05, lambda: self.cmd_vel_publisher.publish(self.command))
        twist = self.odom_msg.twist.twist
        self._wait_until(
            lambda: abs(self.odom_msg.twist.twist.linear.x - linear) <= 0.05, 5.0, "the velocity"
        )
        self.out_linear_velocity = twist.linear.x
        self.out_angular_velocity = twist.angular.z
```"""
    ],
    "completing": [
        """        self.node.get_logger().info(f"measured {self.out_linear_velocity:.2f} m/s")
```"""
    ],
    "stopping": [
        """        if self.timer is not None:
            self.timer.cancel()
        for _ in range(3):
            self._stop_base()
            time.sleep(0.05)
```"""
    ],
    "resetting": [
        """        if self.timer is not None:
            self.timer.cancel()
        self._stop_base()
        self.out_linear_velocity = 0.0
        self.out_angular_velocity = 0.0
```"""
    ],
}
"""A scripted model's answers for the shipped set-velocity skill: every check passes."""


@pytest.fixture
def models_file(tmp_path: Path, wordy_gguf: Path) -> Path:
    """A models.toml whose default generation model is the tiny GGUF (large context, room for
    a scripted method)."""
    return write_models_toml(tmp_path / "models.toml", wordy_gguf, context=8192, max_tokens=400)


def use_model(monkeypatch: pytest.MonkeyPatch, model: MethodScript) -> None:
    """Makes the pipeline load ``model`` whatever the registry says."""
    import skillwright.llm

    def load(_registry: object, _model_id: str | None = None, **_: object) -> MethodScript:
        return model

    monkeypatch.setattr(skillwright.llm, "load_generator", load)


def stems(events: Sequence[object], kind: type) -> list[str]:
    return [getattr(e, "stage", "") for e in events if isinstance(e, kind)]
