"""rosbridge's shared state, one manager per concern (rosbridge_suite's internal/publishers.py,
subscribers.py, services): topics (the lab's sampled topics and the nodes' topics, their
publishers and subscriptions), services, actions, tf (the programs' frames and the
tf2_web_republisher), windows (cv2.imshow images) and sessions (the connected clients). The Bridge
(app/rosbridge/bridge.py) holds one of each; the capabilities call their methods."""
