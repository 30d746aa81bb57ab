"""rclpy.exceptions (the ones a program meets)."""


class NotInitializedException(Exception):
    def __init__(self, *args):
        super().__init__("rclpy.init() has not been called", *args)


class ParameterException(Exception):
    def __init__(self, error_msg, parameters, *args):
        super().__init__(f"{error_msg}: {parameters}", *args)


class ParameterNotDeclaredException(ParameterException):
    def __init__(self, parameters, *args):
        super().__init__("Invalid access to undeclared parameter(s)", parameters, *args)


class ParameterAlreadyDeclaredException(ParameterException):
    def __init__(self, parameters, *args):
        super().__init__("Parameter(s) already declared", parameters, *args)


class InvalidParameterException(ParameterException):
    def __init__(self, parameter, *args):
        super().__init__("Invalid parameter name", parameter, *args)


class InvalidParameterValueException(ParameterException):
    def __init__(self, parameter, value, reason, *args):
        self.reason = reason
        Exception.__init__(self, f"Invalid parameter value ({value}) for parameter. Reason: {reason}", parameter, *args)


class InvalidParameterTypeException(ParameterException):
    def __init__(self, desired_parameter, expected_type, *args):
        Exception.__init__(self, f"Trying to set parameter '{desired_parameter.name}' to '{desired_parameter.value}' "
                                 f"of type '{desired_parameter.type_.name}', expecting type '{expected_type}'", *args)


class ParameterUninitializedException(ParameterException):
    def __init__(self, parameter, *args):
        Exception.__init__(self, f"The parameter '{parameter}' is not initialized", *args)


class ROSInterruptException(Exception):
    pass


class ServiceCallFailed(Exception):
    """The lab reported the call as failed (no such service, the node that serves it failed or did
    not answer, a refused request): set on the call's future. ROS 2 itself has no failed calls."""


class RCLError(RuntimeError):
    """rcl could not do what was asked (rclpy raises it from its C layer as `_rclpy.RCLError`): here,
    the lab refused to create an entity, e.g. a service whose name another node already provides."""


class InvalidHandle(Exception):
    """An entity used after it was destroyed."""
