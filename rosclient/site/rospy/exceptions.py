"""rospy's exceptions, as rospy.exceptions defines them."""


class ROSException(Exception):
    """rospy's base exception (e.g. wait_for_service's timeout)."""


class ROSSerializationException(ROSException):
    """A message that cannot be written (a field of the wrong type or range)."""


class ROSInitException(ROSException):
    """The node cannot start (or an API that needs init_node ran before it)."""


class ROSInterruptException(ROSException, KeyboardInterrupt):
    """Raised by sleep() and Rate.sleep() when the node shuts down."""


class ROSTimeMovedBackwardsException(ROSInterruptException):
    """Raised by sleep() when simulated time jumps back."""

    def __init__(self, time: float) -> None:
        self.time = time
        super().__init__("ROS time moved backwards")


class ROSInternalException(Exception):
    """A fault of the client library itself."""


class TransportException(ROSException):
    """The connection to the lab failed."""


class TransportTerminated(TransportException):
    pass


class TransportInitError(TransportException):
    pass
