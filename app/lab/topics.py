"""The lab's topics (docs/design.md, "The ROS vocabulary over HTTP"): the ones a recording stores
(sim/messages.py, so headless trials record them too), franka_states, which nodes read, the
frames (/tf, /tf_static: app/lab/tf.py) and the camera's (/image_raw, /camera_info: docs/camera.md).

/image_raw is not built from a snapshot but from the camera process's latest image
(`Lab.camera`, app/runtime/camera_process.py): its readers (app/api/topics.py, app/api/camera.py,
the rosbridge subscription, the recorder) hold the camera's demand and send `image_message` of
each new frame; its entry here (an empty image) gives its name, type and the message's shape."""

import threading

import numpy as np

from sim.messages import TOPICS as RECORDED_TOPICS
from sim.messages import Topic, camera_info, header, image
from sim.robot.panda import PandaModel
from sim.world import Snapshot

from app.lab import tf
from app.runtime.camera_process import IMAGE

CAMERA_INFO = "/camera_info"

_MODEL_LOCK = threading.Lock()
_MODEL: list[PandaModel] = []  # one model for the Jacobian, made on first use (pinocchio's data is not thread-safe)


def franka_state(s: Snapshot) -> dict:
    """What franka_state_controller publishes, the lab's subset: q, dq, O_T_EE (4x4, column-major),
    K_F_ext_hat_K (= F_ext) and O_Jac_EE, the flange Jacobian in the base frame (6x7,
    column-major like libfranka's zeroJacobian: twist_base = J qdot)."""
    with _MODEL_LOCK:
        if not _MODEL:
            _MODEL.append(PandaModel())
        jacobian = np.array(_MODEL[0].jacobian_base(s.q))
    return {
        "header": header(s, "panda_link0"),
        "q": s.q.tolist(),
        "dq": s.qdot.tolist(),
        "O_T_EE": s.transform_ee_to_base.flatten(order="F").tolist(),
        "K_F_ext_hat_K": s.wrench_ee.tolist(),
        "O_Jac_EE": jacobian.flatten(order="F").tolist(),
    }


TOPICS = [
    *RECORDED_TOPICS,
    Topic("/franka_state_controller/franka_states", "hri_lab/FrankaState", franka_state),
    Topic("/tf", "tf2_msgs/TFMessage", tf.tf),
    Topic("/tf_static", "tf2_msgs/TFMessage", tf.tf_static),
    Topic(IMAGE, "sensor_msgs/Image", lambda s: image(s.time, np.zeros((0, 0, 3), np.uint8))),
    Topic(CAMERA_INFO, "sensor_msgs/CameraInfo", camera_info),
]
# at most this often to one subscriber (s): the frames cost a forward kinematics each (tf2's
# broadcasters publish at tens of Hz)
MIN_PERIOD_S = {"/tf": 0.01, "/tf_static": 0.1, CAMERA_INFO: 1 / 30}
# sent again only when it changed (ROS's latched / transient-local topics)
LATCHED = {"/tf_static"}
