"""A package's executables as `ros2 run` / `rosrun` find them (rosclient/executables.py): the
workspaces searched, setup.py's and setup.cfg's entry points read without running them, rosrun's
search of the whole package, and a program whose main() nothing calls."""

from pathlib import Path

import pytest

from rosclient import executables as ex
from tests.ros_running import PROGRAMS

COURSE = PROGRAMS / "course_ws"


def _package(folder: Path, name: str, build: str = "ament_python") -> Path:
    folder.mkdir(parents=True)
    (folder / "package.xml").write_text(
        f"<package format='3'><name>{name}</name><export><build_type>{build}</build_type></export></package>"
    )
    return folder


def test_the_course_packages_entry_points_are_found_from_inside_the_workspace():
    roots = ex.workspaces(COURSE / "src" / "lab8" / "lab8", env={})
    assert roots[0] == COURSE.resolve()
    server = ex.resolve("lab8", "myServer", roots)
    assert server.entry == "lab8.my_server:main"  # an f-string of setup.py's package_name
    assert server.program == COURSE.resolve() / "src" / "lab8" / "lab8" / "my_server.py"
    assert server.root == COURSE.resolve() / "src" / "lab8"
    assert ex.resolve("lab8", "myClient", roots).entry == "lab8.my_client:main"  # 'x = ' + package_name + ...
    adder = ex.resolve("learning_service", "service_adder_server", roots)
    assert adder.entry == "learning_service.service_adder_server:main"
    assert adder.workspace == COURSE.resolve()


def test_a_missing_package_or_executable_is_said_as_ros2_run_says_it():
    roots = ex.workspaces(COURSE, env={})
    with pytest.raises(ex.NotFound, match="Package 'lab9' not found"):
        ex.resolve("lab9", "myServer", roots)
    with pytest.raises(ex.NotFound, match=r"No executable found: 'myserver' .*its entry points: myClient, myServer"):
        ex.resolve("lab8", "myserver", roots)


def test_setup_cfg_entry_points_and_a_setup_py_that_is_not_literal(tmp_path):
    pkg = _package(tmp_path / "ws" / "src" / "talkers", "talkers")
    (pkg / "talkers").mkdir()
    (pkg / "talkers" / "__init__.py").write_text("")
    (pkg / "setup.cfg").write_text(
        "[options.entry_points]\nconsole_scripts =\n    talker = talkers.talk:main\n    listener=talkers.listen:run [extra]\n"
    )
    (pkg / "setup.py").write_text("from setuptools import setup\nsetup(entry_points=load_them())\n")
    assert ex.entry_points(pkg) == {"talker": "talkers.talk:main", "listener": "talkers.listen:run"}
    (pkg / "setup.py").write_text(
        "import setuptools\nsetuptools.setup(entry_points={'console_scripts': ['a = b.c:d']})"
    )
    assert ex.entry_points(pkg)["a"] == "b.c:d"
    (pkg / "setup.py").write_text("def setup(:\n")  # not Python: no entry points from it, no exception
    assert ex.entry_points(pkg) == {"talker": "talkers.talk:main", "listener": "talkers.listen:run"}


def test_rosrun_finds_a_script_anywhere_in_a_catkin_package_from_any_folder(tmp_path):
    ws = tmp_path / "home" / "catkin_ws"
    pkg = _package(ws / "src" / "turtle_teleop", "turtle_teleop", "catkin")
    (pkg / "nodes").mkdir()
    (pkg / "nodes" / "teleop.py").write_text("print('hi')\n")
    (pkg / "build").mkdir()
    (pkg / "build" / "teleop.py").write_text("")  # a build folder is not searched
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    # from any folder: the home folder's *_ws workspaces (as a sourced setup.bash would have them)
    roots = ex.workspaces(elsewhere, env={"HOME": str(tmp_path / "home")})
    assert roots == [ws.resolve()]
    found = ex.resolve("turtle_teleop", "teleop.py", roots)
    assert found.script == (pkg / "nodes" / "teleop.py").resolve() and found.entry is None
    # ROS_PACKAGE_PATH, and --workspace / $HRI_LAB_WORKSPACE before everything else
    other = tmp_path / "other_ws"
    _package(other / "src" / "turtle_teleop", "turtle_teleop", "catkin")
    env = {"HOME": str(elsewhere), "ROS_PACKAGE_PATH": str(ws / "src"), "HRI_LAB_WORKSPACE": str(other)}
    assert ex.workspaces(elsewhere, env=env) == [other.resolve(), (ws / "src").resolve()]
    assert ex.workspaces(elsewhere, str(ws), env=env)[0] == ws.resolve()


def test_a_src_folder_without_packages_is_no_workspace(tmp_path):
    (tmp_path / "project" / "src").mkdir(parents=True)
    assert ex.workspaces(tmp_path / "project", env={"HOME": str(tmp_path)}) == []


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("def main(args=None):\n    pass\n", "call"),
        ("def main():\n    pass\n", "call"),
        ("def main(args=None):\n    pass\nif __name__ == '__main__':\n    main()\n", None),
        ("def main():\n    pass\nmain()\n", None),  # called at the top level
        ("def main(argv):\n    pass\n", "needs arguments"),
        ("import rospy\nrospy.init_node('x')\n", None),  # no main(): runs as it is
        ("async def main():\n    pass\n", None),
        ("def main(:\n", None),
    ],
)
def test_main_without_a_main_block_is_called(source, expected):
    assert ex.main_call(source) == expected


def test_the_adder_server_file_is_one_whose_main_is_called():
    source = (COURSE / "src/learning_service/learning_service/service_adder_server.py").read_text()
    assert ex.main_call(source) == "call"
