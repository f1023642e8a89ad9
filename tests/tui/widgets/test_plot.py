"""Braille line plots: the dots land where the data says, the axes keep their ranges."""

from __future__ import annotations

from skillwright.tui.widgets.plot import Series, braille_plot


def _grid(text: str, rows: int) -> list[str]:
    """The plot's cells without the axis labels."""
    return [line.split("│", 1)[1] for line in text.splitlines()[:rows]]


def test_a_diagonal_runs_from_the_lower_left_to_the_upper_right_cell() -> None:
    text = braille_plot(
        [Series([(0.0, 0.0), (1.0, 1.0)], "blue", "run")],
        4,
        2,
        x_label="x",
        y_label="y",
    ).plain
    grid = _grid(text, 2)
    assert grid[1][0] != "⠀"  # blank braille: the line starts at the lower left
    assert grid[0][3] != "⠀"  # and ends at the upper right
    assert grid[0][0] == "⠀"
    assert grid[1][3] == "⠀"
    assert text.splitlines()[0].startswith("1.00 │")
    assert text.splitlines()[1].startswith("0.00 │")
    assert "━ run" in text


def test_equal_axes_keep_a_straight_path_flat_and_a_floor_starts_at_zero() -> None:
    path = braille_plot(
        [Series([(0.0, 0.5), (2.0, 0.5)], "blue", "run")],
        20,
        5,
        x_label="x",
        y_label="y",
        equal_axes=True,
    ).plain
    lines = [line for line in _grid(path, 5) if line.strip("⠀")]
    assert len(lines) == 1  # a line along x stays in one row of cells
    speed = braille_plot(
        [Series([(0.0, 0.2), (1.0, 0.3)], "blue", "run")],
        10,
        3,
        x_label="t",
        y_label="v",
        y_floor=0.0,
    ).plain
    assert speed.splitlines()[2].startswith("0.00 │")


def test_nothing_to_plot_says_so() -> None:
    assert braille_plot([Series([], "blue", "run")], 10, 3, x_label="x", y_label="y").plain == (
        "(nothing to plot)"
    )
