"""The 3D scene draws what the simulation says: arrows from F_ext, colours from the state."""

import numpy as np
import pytest

from sim.messages import wrench_stamped

from app.lab import commands
from app.lab.actions import ACTIONS
from app.lab.lab import Lab
from app.lab.services import SERVICES
from app.lab.view import FORCE_SCALE, LabView, state_of
from app.ros.actions import ActionServer
from tests.app.view.looking import a_browser
from tests.waiting import wait_for


@pytest.fixture(scope="module")
def view():
    lab = Lab(realtime=False)
    view = LabView(lab, ActionServer(ACTIONS, lab), SERVICES, port=0, light=True)
    yield view
    view.server.stop()


def test_force_arrow_follows_f_ext(view):
    lab = view.lab
    lab.runtime.world.start_lifting(10.0)
    lab.runtime.world.run(1.5)  # pressing the box
    snapshot = lab.runtime.world.snapshot()
    view.update(snapshot)
    message = wrench_stamped(snapshot)  # what /franka_state_controller/F_ext publishes
    f_ee = np.array([message["wrench"]["force"][k] for k in "xyz"])
    rotation = snapshot.transform_ee_to_base[:3, :3]
    normal = rotation[:, 2]
    f_world = rotation @ f_ee
    start, end = view.shapes.arrows["normal"].points[0]
    centre = snapshot.transform_ee_to_base[:3, 3] + normal * lab.runtime.world.config.plate.offset
    assert start == pytest.approx(centre, abs=1e-6)  # viser stores float32
    assert end - start == pytest.approx(FORCE_SCALE * (f_world @ normal) * normal, abs=1e-6)
    start_t, end_t = view.shapes.arrows["tangential"].points[0]
    assert end_t - start_t == pytest.approx(FORCE_SCALE * (f_world - (f_world @ normal) * normal), abs=1e-6)
    assert f_ee[2] > 5.0  # pressing: a visible normal arrow along the plate normal (base +y)
    assert (end - start)[1] > 0.05
    # the robot's meshes follow q (flange link placed by pinocchio)
    assert view.robot.frames
    assert np.allclose(view.shapes.box.position, snapshot.box_position)


def test_colours_tell_the_state(view):
    world = view.lab.runtime.world
    world.reset()
    world.start_lifting(10.0)
    world.run(1.5)  # pressing the box (whatever the tests before left)
    snapshot = world.snapshot()
    assert state_of(snapshot) in ("inside", "below", "above", "slipping")
    world.stop_lifting()
    assert state_of(world.snapshot()) in ("idle", "slipping")
    world.arm.error = "cartesian velocity limit: test"
    assert state_of(world.snapshot()) == "error"
    world.recover()


def test_dragging_the_palm_gizmo_up_makes_the_robot_follow(view):
    """The gizmo's callback moves the person's hand target; the robot follows only through the SP
    controller (pressing, then friction beyond the cone margin)."""
    world = view.lab.runtime.world
    world.reset()
    world.start_lifting(10.0)
    while not world.human.holding_by_contact:  # the person lets go once the grip is in the band
        world.step()
    world.run(0.5)
    ee_before = world.arm.transform_ee_to_base[2, 3]
    box_before = world.box.position[2]
    start = world.human.hand.copy()
    for k in range(1, 41):  # drag up 8 cm over 2 s
        view.gizmo.position = start + [0.0, 0.0, 0.002 * k]
        view._on_gizmo(None)
        world.run(0.05)
    world.run(1.0)
    assert world.human.phase == "manual"
    assert world.box.position[2] - box_before > 0.06  # the box went up with the hand
    assert world.arm.transform_ee_to_base[2, 3] - ee_before > 0.05  # and the robot followed
    assert world.plate_state.normal_force > 5.0
    assert world.error is None


def test_legend_names_every_colour_and_arrow():
    from app.lab.view import ARROWS, COLOURS, MEANING, legend_markdown

    legend = legend_markdown()
    assert set(MEANING) == set(COLOURS)  # the idle colour included
    for key, rgb in COLOURS.items():
        assert f"rgb{rgb}" in legend
        assert MEANING[key] in legend
    for rgb, text in ARROWS.values():
        assert f"rgb{rgb}" in legend
        assert text in legend


def test_status_is_current_whatever_changed_the_state(view):
    """Lifting started outside the view (as curl would) shows in the view's status at the next frame."""
    world = view.lab.runtime.world
    world.stop_lifting()
    world.reset()
    view.update(world.snapshot())
    assert "lifting **off**" in view.status.content
    assert "True" not in view.status.content
    world.start_lifting(12.0)  # not through the view
    world.run(0.05)
    view.update(world.snapshot())
    assert "lifting **on**, band [12, 17] N" in view.status.content
    assert "trial running" in view.status.content
    world.stop_lifting()


def test_take_over_stops_the_scripted_person_and_keeps_the_gizmo(view):
    world = view.lab.runtime.world
    world.reset()
    world.start_lifting(10.0)
    world.run(0.01)
    view.update(world.snapshot())
    assert not view.take_over.value
    view.take_over.value = True
    view._on_take_over(None)  # what viser calls when the box is ticked
    world.run(0.05)
    view.update(world.snapshot())
    assert world.human.phase == "manual"
    assert world.trial.state == "abandoned"
    held = np.array(view.gizmo.position)
    view.gizmo.position = held + [0.0, 0.0, 0.05]  # the user's drag is not overwritten by the palm
    view.update(world.snapshot())
    assert np.allclose(view.gizmo.position, held + [0.0, 0.0, 0.05])
    assert view.take_over.value


def test_the_default_camera_frames_the_robot_and_the_box_beside_the_panel(view):
    """Every robot mesh origin, the box's corners and the palm project inside the canvas the docked
    control panel leaves free in the dashboard's embedded view (872 x 414 px with a 1500 x 900
    window), through viser's pinhole camera (the view's position, look-at, vertical fov, +z up);
    the gizmo keeps a fixed on-screen size, clearly larger than a fingertip."""
    from app.lab.view import GIZMO_SIZE
    from app.view.scene import PANEL_WIDTH

    camera = view.server.initial_camera
    forward = np.asarray(camera.look_at) - np.asarray(camera.position)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    height_px, width_px = 414, 872 - PANEL_WIDTH
    focal_px = (height_px / 2) / np.tan(camera.fov / 2)
    world = view.lab.runtime.world
    world.reset()
    s = world.snapshot()
    view.update(s)
    half = np.array(view.lab.call(commands.scene_geometry)["box"]) / 2
    corners = [s.box_position + s.box_rotation @ (half * [i, j, k]) for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)]
    lifted = [c + [0.0, 0.0, 0.2] for c in corners]  # where a lift takes it
    for point in [np.asarray(f.position) for _, f in view.robot.frames] + corners + lifted + [s.palm_position]:
        rel = point - np.asarray(camera.position)
        depth = rel @ forward
        x_px, y_px = focal_px * (rel @ right) / depth, focal_px * (rel @ up) / depth
        assert abs(x_px) < 0.95 * width_px / 2 and abs(y_px) < 0.95 * height_px / 2, (point, x_px, y_px)
    assert view.gizmo.fixed
    assert view.gizmo.scale == GIZMO_SIZE >= 80


def test_it_draws_only_while_a_browser_looks():
    """Nobody looking, the view's thread keeps the box's path and draws nothing; a browser that
    connects is drawn for; once it leaves, nothing again."""
    lab = Lab(realtime=False)
    view = LabView(lab, ActionServer(ACTIONS, lab), SERVICES, port=0, light=True, rate_hz=200.0)
    view.start()  # the first frame, drawn at the start: what a browser that connects is sent
    try:
        drawn, kept = len(view.frame_times), len(view._path)
        wait_for(lambda: len(view._path) >= kept + 5)  # five periods of the thread
        assert len(view.frame_times) == drawn == 1
        with a_browser(view.server):
            wait_for(lambda: len(view.frame_times) >= drawn + 3)
        drawn, kept = len(view.frame_times), len(view._path)
        wait_for(lambda: len(view._path) >= kept + 5)
        assert len(view.frame_times) <= drawn + 1  # at most the frame begun as the browser left
    finally:
        view.stop()
        lab.stop()
