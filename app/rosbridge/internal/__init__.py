"""The pieces the shared state is made of (rosbridge_suite's `internal/`): a topic as one client
receives it (streams.py), the frames programs publish (node_frames.py). Imported by the bridge
(app/rosbridge/bridge.py), the capabilities and the session, never importing them."""
