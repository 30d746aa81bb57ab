"""ROS interfaces as text and as classes, shared by the lab's server and the programs' client:

- parser.py: .msg/.srv/.action text -> fields and constants
- messages.py: the classes of parsed messages (ROS defaults, rosbridge's JSON)
- packages.py: interface packages in search roots, made classes on demand; a definition as carried text
- image_windows.py: the topics programs' `cv2.imshow` windows go on (the dashboard shows them)
- share/: the standard packages' definitions and the lab's own `hri_lab` (its .srv/.action files
  generated from the lab's declarations: `python -m app.lab.interface_files`)
"""
