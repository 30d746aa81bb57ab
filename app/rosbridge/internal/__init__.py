"""The pieces the shared state is made of (rosbridge_suite's `internal/`): a topic as one client
receives it (streams.py), what its streams share (shared.py), the frames programs publish
(node_frames.py), a relayed message made whole (message_conversion.py). Imported by the managers
(app/rosbridge/managers/), the capabilities and the session, never importing them."""
