"""Stand-in of ``rclpy.exceptions``."""


class NotInitializedException(Exception):
    def __init__(self, cause: str = "") -> None:
        super().__init__(f"rclpy.init() has not been called {cause}".strip())


class InvalidTopicNameException(Exception):
    def __init__(self, name: str, error: str = "") -> None:
        super().__init__(f"Invalid topic name '{name}': {error}".rstrip(": "))


class InvalidServiceNameException(Exception):
    def __init__(self, name: str, error: str = "") -> None:
        super().__init__(f"Invalid service name '{name}': {error}".rstrip(": "))


class ParameterException(Exception):
    def __init__(self, error: str, parameters: object = None) -> None:
        super().__init__(f"{error}: {parameters}" if parameters is not None else error)


class ParameterNotDeclaredException(ParameterException):
    def __init__(self, parameters: object) -> None:
        super().__init__("Invalid access to undeclared parameter(s)", parameters)


class ParameterAlreadyDeclaredException(ParameterException):
    def __init__(self, parameters: object) -> None:
        super().__init__("Parameter(s) already declared", parameters)


class InvalidParameterValueException(ParameterException):
    def __init__(self, parameter: object, value: object, reason: str = "") -> None:
        super().__init__(
            f"Invalid parameter value ({value}) for parameter. Reason: {reason}", parameter
        )


class ParameterUninitializedException(ParameterException):
    def __init__(self, parameter_name: str) -> None:
        super().__init__(f"The parameter '{parameter_name}' is not initialized")


class ROSInterruptException(Exception):
    pass
