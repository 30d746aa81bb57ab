"""cv_bridge (rosclient/site/cv_bridge): an image goes to a sensor_msgs/Image and back unchanged, a
big-endian message is read in its byte order, a colour image converts to mono8 with OpenCV's weights,
and what cannot be converted is refused with cv_bridge's error."""

import numpy as np
import pytest


def test_an_image_goes_to_a_message_and_back(site):
    from cv_bridge import CvBridge

    image = np.arange(2 * 3 * 3, dtype=np.uint8).reshape(2, 3, 3)
    msg = CvBridge().cv2_to_imgmsg(image, encoding="rgb8")
    assert (msg.height, msg.width, msg.step, msg.encoding) == (2, 3, 9, "rgb8")
    back = CvBridge().imgmsg_to_cv2(msg)
    assert back.dtype == np.uint8 and np.array_equal(back, image)
    bgr = CvBridge().imgmsg_to_cv2(msg, desired_encoding="bgr8")
    assert np.array_equal(bgr, image[..., ::-1])


def test_a_big_endian_depth_image_is_read_in_its_byte_order(site):
    from cv_bridge import CvBridge
    from sensor_msgs.msg import Image

    depth = np.array([[1, 256], [513, 65535]], dtype=">u2")
    msg = Image(height=2, width=2, encoding="16UC1", is_bigendian=1, step=4, data=depth.tobytes())
    assert CvBridge().imgmsg_to_cv2(msg).tolist() == [[1, 256], [513, 65535]]


def test_grey_has_opencvs_weights(site):
    from cv_bridge import CvBridge

    image = np.array([[[255, 0, 0], [0, 255, 0], [0, 0, 255]]], dtype=np.uint8)  # pure R, G, B
    grey = CvBridge().imgmsg_to_cv2(CvBridge().cv2_to_imgmsg(image, "rgb8"), desired_encoding="mono8")
    assert grey.tolist() == [[76, 150, 29]]  # 0.299, 0.587, 0.114 of 255, rounded


def test_what_cannot_be_converted_is_refused(site):
    from cv_bridge import CvBridge, CvBridgeError
    from sensor_msgs.msg import Image

    with pytest.raises(CvBridgeError, match="Unrecognized image encoding"):
        CvBridge().imgmsg_to_cv2(Image(height=1, width=1, encoding="yuv422", step=2, data=b"\0\0"))
    with pytest.raises(CvBridgeError, match="too short"):
        CvBridge().imgmsg_to_cv2(Image(height=2, width=2, encoding="mono8", step=2, data=b"\0\0"))
    with pytest.raises(CvBridgeError, match="incompatible type"):
        CvBridge().cv2_to_imgmsg(np.zeros((2, 2), dtype=np.float32), encoding="mono8")
