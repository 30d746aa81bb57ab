"""What the runtime needs from a world (app/runtime/loop.py steps it, app/runtime/process.py forks
it): any world's simulation — the lifting world's (sim/world.py), the mobile one's
(sim/mobile/world.py) or another — as a typed Protocol. `S_co` is the world's snapshot type."""

from __future__ import annotations

from typing import Protocol, TypeVar

S_co = TypeVar("S_co", covariant=True)


class Stepped(Protocol):
    """A world's configuration, as far as the loop reads it."""

    @property
    def dt(self) -> float:
        """s of simulated time one step advances."""
        ...


class Simulated(Protocol[S_co]):
    """A world the loop steps, publishes and stops with a reason."""

    @property
    def config(self) -> Stepped: ...

    @property
    def time(self) -> float:
        """s of simulated time."""
        ...

    @property
    def commanded(self) -> bool:
        """Something moves or is commanded to (the loop keeps its fine granularity then)."""
        ...

    def step(self) -> None: ...

    def snapshot(self) -> S_co: ...

    def fail(self, reason: str) -> None:
        """A step failed: the world says why in its snapshots."""
        ...
