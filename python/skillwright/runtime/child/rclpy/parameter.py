"""Stand-in of ``rclpy.parameter``."""

from __future__ import annotations

from enum import IntEnum
from types import SimpleNamespace


class Parameter:
    """A node parameter: name, type and value."""

    class Type(IntEnum):
        NOT_SET = 0
        BOOL = 1
        INTEGER = 2
        DOUBLE = 3
        STRING = 4
        BYTE_ARRAY = 5
        BOOL_ARRAY = 6
        INTEGER_ARRAY = 7
        DOUBLE_ARRAY = 8
        STRING_ARRAY = 9

        @classmethod
        def from_parameter_value(cls, value: object) -> Parameter.Type:
            if value is None:
                return cls.NOT_SET
            if isinstance(value, bool):
                return cls.BOOL
            if isinstance(value, int):
                return cls.INTEGER
            if isinstance(value, float):
                return cls.DOUBLE
            if isinstance(value, str):
                return cls.STRING
            if isinstance(value, (bytes, bytearray)):
                return cls.BYTE_ARRAY
            if isinstance(value, (list, tuple)):
                if all(isinstance(v, bool) for v in value):
                    return cls.BOOL_ARRAY
                if all(isinstance(v, int) for v in value):
                    return cls.INTEGER_ARRAY
                if all(isinstance(v, float) for v in value):
                    return cls.DOUBLE_ARRAY
                if all(isinstance(v, str) for v in value):
                    return cls.STRING_ARRAY
            raise TypeError(f"The given value is not one of the allowed types '{value}'.")

    def __init__(
        self, name: str, type_: Parameter.Type | None = None, value: object = None
    ) -> None:
        if type_ is None:
            type_ = Parameter.Type.from_parameter_value(value)
        self._name = name
        self._type = Parameter.Type(type_)
        self._value = value

    @property
    def name(self) -> str:
        return self._name

    @property
    def type_(self) -> Parameter.Type:
        return self._type

    @property
    def value(self) -> object:
        return self._value

    def get_parameter_value(self) -> SimpleNamespace:
        value = self._value
        kind = self._type
        return SimpleNamespace(
            type=int(kind),
            bool_value=value if kind == Parameter.Type.BOOL else False,
            integer_value=value if kind == Parameter.Type.INTEGER else 0,
            double_value=value if kind == Parameter.Type.DOUBLE else 0.0,
            string_value=value if kind == Parameter.Type.STRING else "",
            byte_array_value=list(value) if kind == Parameter.Type.BYTE_ARRAY else [],  # type: ignore[call-overload]
            bool_array_value=list(value) if kind == Parameter.Type.BOOL_ARRAY else [],  # type: ignore[call-overload]
            integer_array_value=list(value) if kind == Parameter.Type.INTEGER_ARRAY else [],  # type: ignore[call-overload]
            double_array_value=list(value) if kind == Parameter.Type.DOUBLE_ARRAY else [],  # type: ignore[call-overload]
            string_array_value=list(value) if kind == Parameter.Type.STRING_ARRAY else [],  # type: ignore[call-overload]
        )

    def __repr__(self) -> str:
        return f"Parameter(name={self._name!r}, type_={self._type.name}, value={self._value!r})"
