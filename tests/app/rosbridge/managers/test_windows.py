"""The programs' cv2.imshow windows (app/rosbridge/managers/windows.py): the newest image of each,
a copy for the dashboard, and the window gone with its program (managers/topics.py)."""

from app.lab.world import LIFTING
from app.rosbridge.managers.topics import TopicManager
from app.rosbridge.managers.windows import Windows
from interfaces.image_windows import WINDOWS
from tests.app.rosbridge.clients import connect, parts, run

TOPIC = WINDOWS + "camera"


def test_a_window_shows_its_newest_image_and_the_dashboard_reads_a_copy():
    windows = Windows()
    assert windows.get(TOPIC) is None and windows.shown() == {}
    windows.show(TOPIC, {"data": "first"})
    windows.show(TOPIC, {"data": "newest"})
    shown = windows.shown()
    assert shown == {TOPIC: {"data": "newest"}}
    shown.clear()  # the dashboard's copy: the windows stay
    assert windows.get(TOPIC) == {"data": "newest"}
    windows.close(TOPIC)
    windows.close(TOPIC)  # twice: nothing to close
    assert windows.get(TOPIC) is None


def test_a_window_goes_with_the_last_publisher_of_its_topic():
    async def check() -> None:
        lab = parts(replay=True)
        first, second = await connect(lab), await connect(lab)
        windows = Windows()
        topics = TopicManager(LIFTING, replay=True, windows=windows)
        topics.advertise(TOPIC, "sensor_msgs/Image", first)
        topics.advertise(TOPIC, "sensor_msgs/Image", second)
        windows.show(TOPIC, {"data": "x"})
        topics.unadvertise(TOPIC, first)
        assert windows.get(TOPIC) == {"data": "x"}  # the other program still publishes it
        topics.unadvertise(TOPIC, second)
        assert windows.get(TOPIC) is None

    run(check())
