"""hri-lab simulation: a kinematic Franka Panda with a contact plate, a box, a virtual human.

Pure numpy + pinocchio; never imports the server (app/), fastapi or viser.
"""
