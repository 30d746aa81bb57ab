"""launch's LaunchDescription (rosclient/site/launch/_core.py): get_launch_arguments lists the
DeclareLaunchArgument actions it holds, at its top, in groups and in nested descriptions, in
their order; not those an include or a timer holds (read only when they run)."""

from __future__ import annotations


def test_get_launch_arguments_lists_the_declared_ones_where_launch_walks(site):
    from launch import LaunchDescription
    from launch.actions import DeclareLaunchArgument, GroupAction, IncludeLaunchDescription, LogInfo, TimerAction
    from launch.launch_description_sources import PythonLaunchDescriptionSource

    description = LaunchDescription(
        [
            DeclareLaunchArgument("first", default_value="1"),
            LogInfo(msg="not an argument"),
            GroupAction([DeclareLaunchArgument("in_a_group"), GroupAction([DeclareLaunchArgument("deeper")])]),
            LaunchDescription([DeclareLaunchArgument("in_a_description")]),
            IncludeLaunchDescription(PythonLaunchDescriptionSource("other.launch.py")),
            TimerAction(period=1.0, actions=[DeclareLaunchArgument("later")]),
            DeclareLaunchArgument("last"),
        ]
    )
    assert [a.name for a in description.get_launch_arguments()] == [
        "first",
        "in_a_group",
        "deeper",
        "in_a_description",
        "last",
    ]
