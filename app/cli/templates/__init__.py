"""The roslibpy nodes `hri-lab template services|node` prints (scripts, not imported)."""
