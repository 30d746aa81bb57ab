"""The mobile world as a world is declared (app/worlds/contract.py): a TurtleBot3 Burger-like base in an
arena (app/mobile/lab.py) with its topics (app/mobile/topics.py), its recording services, /cmd_vel,
its 3D view (app/view/mobile_view.py) and its page (app/mobile/routes.py); its programs are graded by
`hri-lab grade-wall` (app/grading/wall_trial.py)."""

from __future__ import annotations

from sim.mobile.messages import GRADER_TOPICS
from sim.mobile.world import seeded_config

from app.mobile import commands, routes
from app.mobile.lab import MobileLab
from app.mobile.services import SERVICES
from app.mobile.topics import COMMAND_TOPIC, LATCHED, MIN_PERIOD_S, TOPICS
from app.worlds.contract import LabOptions, Running, ViewRequest, World


def make_lab(options: LabOptions) -> MobileLab:
    config = options.config
    if config is None and options.arena_seed is not None:
        config = seeded_config(options.arena_seed)
    return MobileLab(config, options.realtime, options.graded, MOBILE.served_topics(options.graded))


def make_view(request: ViewRequest) -> Running:
    from app.view.mobile_view import MobileView

    return MobileView(request.lab, request.host, request.port, light=request.light)


MOBILE = World(
    name="mobile",
    lab=make_lab,
    topics=TOPICS,
    services=SERVICES,
    command_topic=COMMAND_TOPIC,
    command=commands.drive,
    view=make_view,
    min_period_s=MIN_PERIOD_S,
    latched=frozenset(LATCHED),
    grader_topics=frozenset(GRADER_TOPICS),
    routes=(routes.router,),
    grader="hri-lab grade-wall",
)
