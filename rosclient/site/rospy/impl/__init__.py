"""rospy.impl: where rospy keeps its transport; here the services' (tcpros_service.py)."""
