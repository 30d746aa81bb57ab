"""Serving a lab: the composition root (a lab, its API, rosbridge and view in one app) and a lab
server run as a process of its own."""
