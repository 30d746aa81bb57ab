"""A rospy server of the workspace's own ScalePoint.srv, with a nested geometry_msgs/Point and the
package's own Note message: a type the lab knows only from the text the program carries."""

import rospy
from cpp_package.msg import Note
from cpp_package.srv import ScalePoint, ScalePointResponse
from geometry_msgs.msg import Point


def handle_scale_point(req):
    scaled = Point(*(round(v * req.factor, req.digits) for v in (req.point.x, req.point.y, req.point.z)))
    rospy.loginfo("scaled (%s, %s, %s) by %s", req.point.x, req.point.y, req.point.z, req.factor)
    return ScalePointResponse(scaled, Note("scaled by %g" % req.factor, 1))


if __name__ == "__main__":
    rospy.init_node("point_scaler")
    rospy.Service("scale_point", ScalePoint, handle_scale_point)
    print("Ready to scale points.", flush=True)
    rospy.spin()
