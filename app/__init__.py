"""hri-lab server side: the ROS vocabulary over HTTP, the 3D view and the CLI (reads sim/ snapshots)."""
