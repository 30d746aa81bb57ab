"""Lab 8's launch file, in the style of the ROS 2 documentation's launch tutorials: an argument,
the server in a namespace with a parameter and a remapped service name, the client started by a
timer once the server has started, and the launch shut down when the client exits."""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, EmitEvent, GroupAction, LogInfo, RegisterEventHandler, TimerAction
from launch.event_handlers import OnProcessExit, OnProcessStart
from launch.events import Shutdown
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node, PushRosNamespace


def generate_launch_description():
    offset = LaunchConfiguration("offset")
    server = Node(
        package="lab8",
        executable="myServer",
        name="lab8_server",
        parameters=[{"offset": offset}],
        remappings=[("add_two_ints", "adder")],
        output="screen",
    )
    client = Node(
        package="lab8",
        executable="myClient",
        arguments=["2", "40"],
        remappings=[("add_two_ints", "adder")],
        output="screen",
    )
    return LaunchDescription(
        [
            DeclareLaunchArgument("offset", default_value="0", description="added to every sum"),
            GroupAction([PushRosNamespace("lab8"), server]),
            RegisterEventHandler(
                OnProcessStart(
                    target_action=server,
                    on_start=[
                        LogInfo(msg="server started"),
                        TimerAction(period=1.0, actions=[GroupAction([PushRosNamespace("lab8"), client])]),
                    ],
                )
            ),
            RegisterEventHandler(
                OnProcessExit(
                    target_action=client,
                    on_exit=[LogInfo(msg="client done"), EmitEvent(event=Shutdown(reason="client done"))],
                )
            ),
        ]
    )
