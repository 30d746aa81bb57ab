"""rospy.service: the exception of a failed service (calls and providing)."""

from rospy.exceptions import ROSException


class ServiceException(ROSException):
    """A service call that failed (the service is missing, its handler failed, or the lab refused
    it), or a service that cannot be provided (its name is already taken)."""


__all__ = ["ServiceException"]
