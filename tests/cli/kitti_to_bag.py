"""Writes a KITTI-layout recording's scans as a ROS 1 bag with Debian's python3-rosbag, for the tests.

Usage: /usr/bin/python3 kitti_to_bag.py SEQUENCE_DIR TRAJECTORY OUT.bag [--no-tf]

Each SEQUENCE_DIR/velodyne/NNNNNN.bin (float32 x y z intensity per point) becomes a
sensor_msgs/PointCloud2 on /velodyne_points (frame "velodyne") stamped 1000 + 0.1 k s, and each
image_2/NNNNNN.png, when there is one, a sensor_msgs/CompressedImage (format "png", the file's
bytes) on /camera/image_raw/compressed of frame "camera" with its CameraInfo (calib.txt's P2, no
distortion) on /camera/camera_info; /tf_static places "camera" (the rectified camera 0 of
calib.txt's Tr) in "velodyne". TRAJECTORY (T_W_L per frame, 12
numbers a line, as `artemis run` writes it) becomes nav_msgs/Odometry on /odom of frame
"base_link", which a /tf_static transform puts 1.2 m below and 0.3 m behind the LiDAR, so that
the reader must chain the two to get the LiDAR's poses back (--no-tf leaves that transform out).
"""
import os
import struct
import sys

import numpy as np
import rosbag
import rospy
from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, CompressedImage, PointCloud2, PointField
from std_msgs.msg import Header
from tf2_msgs.msg import TFMessage


def transform(parent, child, T):
    t = TransformStamped(header=Header(stamp=rospy.Time(1000), frame_id=parent), child_frame_id=child)
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = T[:3, 3]
    r = t.transform.rotation
    r.x, r.y, r.z, r.w = quaternion(T[:3, :3])
    return t


def quaternion(R):
    """x, y, z, w of a rotation matrix (Shepperd's method)."""
    t = np.trace(R)
    if t > 0:
        s = 2.0 * np.sqrt(1.0 + t)
        return (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s, 0.25 * s
    i = int(np.argmax(np.diag(R)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * np.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
    q = [0.0, 0.0, 0.0, 0.0]
    q[i] = 0.25 * s
    q[j] = (R[j, i] + R[i, j]) / s
    q[k] = (R[k, i] + R[i, k]) / s
    q[3] = (R[k, j] - R[j, k]) / s
    return tuple(q)


sequence, trajectory, out = sys.argv[1], sys.argv[2], sys.argv[3]
velodyne, images = os.path.join(sequence, "velodyne"), os.path.join(sequence, "image_2")
scans = sorted(f for f in os.listdir(velodyne) if f.endswith(".bin"))
calib = {line.split(":")[0]: np.array(line.split(":")[1].split(), dtype=float)
         for line in open(os.path.join(sequence, "calib.txt")) if ":" in line}
T_C0_L = np.vstack([calib["Tr"].reshape(3, 4), [0, 0, 0, 1]])
poses = [np.vstack([np.array(line.split(), dtype=float).reshape(3, 4), [0, 0, 0, 1]])
         for line in open(trajectory) if line.strip()]
T_base_L = np.eye(4)
T_base_L[:3, 3] = [0.3, 0.0, 1.2]
fields = [PointField(n, 4 * k, PointField.FLOAT32, 1) for k, n in enumerate(["x", "y", "z", "intensity"])]
with rosbag.Bag(out, "w", compression="lz4") as bag:
    if "--no-tf" not in sys.argv[4:]:
        bag.write("/tf_static", TFMessage(transforms=[transform("base_link", "velodyne", T_base_L),
                                                      transform("velodyne", "camera", np.linalg.inv(T_C0_L))]),
                  rospy.Time(1000))
    for k, (scan, T_W_L) in enumerate(zip(scans, poses)):
        t = rospy.Time(1000) + rospy.Duration(0, k * 100_000_000)
        data = open(os.path.join(velodyne, scan), "rb").read()
        n = len(data) // 16
        cloud = PointCloud2(header=Header(seq=k, stamp=t, frame_id="velodyne"), height=1, width=n, fields=fields,
                            is_bigendian=False, point_step=16, row_step=16 * n, data=data, is_dense=False)
        bag.write("/velodyne_points", cloud, t)
        T_W_base = T_W_L @ np.linalg.inv(T_base_L)
        odometry = Odometry(header=Header(seq=k, stamp=t, frame_id="odom"), child_frame_id="base_link")
        p, q = odometry.pose.pose.position, odometry.pose.pose.orientation
        p.x, p.y, p.z = T_W_base[:3, 3]
        q.x, q.y, q.z, q.w = quaternion(T_W_base[:3, :3])
        bag.write("/odom", odometry, t)
        png = os.path.join(images, scan.replace(".bin", ".png"))
        if os.path.exists(png):
            picture = open(png, "rb").read()
            width, height = struct.unpack(">II", picture[16:24])
            bag.write("/camera/image_raw/compressed",
                      CompressedImage(header=Header(seq=k, stamp=t, frame_id="camera"), format="png", data=picture), t)
            info = CameraInfo(header=Header(seq=k, stamp=t, frame_id="camera"), width=width, height=height,
                              distortion_model="plumb_bob", D=[], K=list(calib["P2"].reshape(3, 4)[:, :3].ravel()),
                              R=[1, 0, 0, 0, 1, 0, 0, 0, 1], P=list(calib["P2"]))
            bag.write("/camera/camera_info", info, t)
