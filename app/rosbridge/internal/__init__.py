"""What every rosbridge connection shares (rosbridge_suite's `internal/`): the bridge state, the
services nodes provide, the topic streams. Imported by the capabilities and the session, never
importing them."""
