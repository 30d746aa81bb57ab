"""rclpy.callback_groups: accepted; every callback runs in its node's executor (one thread, or the
MultiThreadedExecutor's pool)."""


class CallbackGroup:
    def __init__(self) -> None:
        self.entities: list = []


class MutuallyExclusiveCallbackGroup(CallbackGroup):
    pass


class ReentrantCallbackGroup(CallbackGroup):
    pass
