"""The topics a program's `cv2.imshow` windows go on: rosclient/windows.py publishes each window
there; the lab keeps each one's newest image (app/rosbridge/capabilities/publish.py) for the
dashboard (app/api/camera.py)."""

WINDOWS = "/image_windows/"
