"""Stand-in of ``rclpy.callback_groups``: every callback runs on the executor's thread."""


class CallbackGroup:
    def __init__(self) -> None:
        self.entities: set = set()

    def add_entity(self, entity: object) -> None:
        self.entities.add(entity)

    def has_entity(self, entity: object) -> bool:
        return entity in self.entities

    def can_execute(self, entity: object) -> bool:
        return True


class ReentrantCallbackGroup(CallbackGroup):
    pass


class MutuallyExclusiveCallbackGroup(CallbackGroup):
    pass
