"""Pulling the Python file out of whatever a model wrapped it in.

Models answer with a fenced block, several blocks, prose around a block, a block cut off at
the token limit, or bare code. The largest Python block that defines a class wins; an
unclosed fence gives everything after it; with no fence at all, leading prose lines are
dropped up to the first line that looks like Python.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Literal

__all__ = ["ExtractedCode", "extract_code"]

_FENCE = re.compile(r"^[ \t]*```[ \t]*([\w+-]*)[ \t]*$", re.MULTILINE)
_PYTHON_START = re.compile(r"^(import |from |@|class |def |\"\"\"|'''|#)")


@dataclass(frozen=True)
class ExtractedCode:
    """The code found in a model's answer, and how it was found."""

    code: str
    method: Literal["fenced", "unclosed fence", "bare", "empty"]


def _blocks(text: str) -> tuple[list[tuple[str, str]], str | None]:
    """Closed fenced blocks (language, body) and the body of a trailing unclosed one."""
    blocks: list[tuple[str, str]] = []
    fences = list(_FENCE.finditer(text))
    index = 0
    while index < len(fences):
        opening = fences[index]
        if index + 1 >= len(fences):
            return blocks, text[opening.end() :].lstrip("\n")
        closing = fences[index + 1]
        blocks.append((opening.group(1).lower(), text[opening.end() : closing.start()].strip("\n")))
        index += 2
    return blocks, None


def extract_code(answer: str) -> ExtractedCode:
    """The Python source in ``answer`` (always ends with a newline unless empty)."""
    blocks, unclosed = _blocks(answer)
    python = [body for language, body in blocks if language in ("python", "py", "python3", "")]
    if python:
        with_class = [body for body in python if re.search(r"^class ", body, re.MULTILINE)]
        best = max(with_class or python, key=len)
        return ExtractedCode(best.rstrip() + "\n", "fenced")
    if unclosed is not None and unclosed.strip():
        return ExtractedCode(unclosed.rstrip() + "\n", "unclosed fence")
    lines = answer.splitlines()
    for start, line in enumerate(lines):
        if _PYTHON_START.match(line):
            code = "\n".join(lines[start:]).rstrip()
            return ExtractedCode(code + "\n", "bare")
    return ExtractedCode("", "empty")
