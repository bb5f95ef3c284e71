"""Writes a small ROS 1 bag with Debian's python3-rosbag (not ARTEMIS's own code), for the tests.

Usage: /usr/bin/python3 write_test_bag.py OUT.bag none|bz2|lz4

One second of a rig: a LiDAR's PointCloud2 at 10 Hz (3 points each, x y z intensity t, frame
"velodyne"), a camera's raw and compressed images and its CameraInfo at 10 Hz, an IMU at 100 Hz,
odometry at 10 Hz (base_link driving 0.5 m a frame along the odometry's y, turned 90 degrees)
and the static transforms of the LiDAR (1.7 m above base_link) and of the camera (0.1 m ahead of
the LiDAR, looking along its x). Bag times start at 1000 s.
"""
import struct
import sys

import rosbag
import rospy
from geometry_msgs.msg import TransformStamped, Vector3
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, CompressedImage, Image, Imu, PointCloud2, PointField
from std_msgs.msg import Header
from tf2_msgs.msg import TFMessage

out, compression = sys.argv[1], sys.argv[2]
with rosbag.Bag(out, "w", compression=compression) as bag:
    for i in range(10):
        t = rospy.Time(1000, i * 100_000_000)
        # Point k: x y z intensity = i + 4k + 0..3, and Ouster's per-point time "t" = k ms (in ns).
        cloud = PointCloud2(header=Header(seq=i, stamp=t, frame_id="velodyne"), height=1, width=3,
                            fields=[PointField("x", 0, PointField.FLOAT32, 1), PointField("y", 4, PointField.FLOAT32, 1),
                                    PointField("z", 8, PointField.FLOAT32, 1),
                                    PointField("intensity", 12, PointField.FLOAT32, 1),
                                    PointField("t", 16, PointField.UINT32, 1)],
                            is_bigendian=False, point_step=20, row_step=60, is_dense=True,
                            data=b"".join(struct.pack("<4fI", *[float(i + 4 * k + j) for j in range(4)], k * 1_000_000)
                                          for k in range(3)))
        bag.write("/velodyne_points", cloud, t)
        image = Image(header=Header(seq=i, stamp=t + rospy.Duration(0, 10_000_000), frame_id="camera"), height=2,
                      width=3, encoding="rgb8",
                      is_bigendian=0, step=9, data=bytes(range(18)))
        bag.write("/camera/image_raw", image, t)
        bag.write("/camera/image_raw/compressed",
                  CompressedImage(header=Header(seq=i, stamp=t), format="jpeg", data=b"\xff\xd8\xff\xd9"), t)
        bag.write("/camera/camera_info",
                  CameraInfo(header=Header(seq=i, stamp=t, frame_id="camera"), height=2, width=3,
                             distortion_model="plumb_bob", D=[0.0] * 5, K=[2, 0, 1, 0, 2, 0.5, 0, 0, 1],
                             R=[1, 0, 0, 0, 1, 0, 0, 0, 1], P=[2, 0, 1, 0, 0, 2, 0.5, 0, 0, 0, 1, 0]), t)
        odometry = Odometry(header=Header(seq=i, stamp=t, frame_id="odom"), child_frame_id="base_link")
        odometry.pose.pose.position.x = 0.5 * i  # driving along x, turned 90 degrees about z
        odometry.pose.pose.orientation.z = 2 ** -0.5
        odometry.pose.pose.orientation.w = 2 ** -0.5
        bag.write("/odom", odometry, t)
    for i in range(100):
        t = rospy.Time(1000, i * 10_000_000)
        # As a Livox driver fills it: rates and accelerations, the orientation left all zeros.
        bag.write("/imu/data", Imu(header=Header(seq=i, stamp=t, frame_id="imu"),
                                   angular_velocity=Vector3(0.0, 0.0, 0.01 * i),
                                   linear_acceleration=Vector3(0.1, 0.0, 9.81)), t)
    transform = TransformStamped(header=Header(stamp=rospy.Time(1000), frame_id="base_link"), child_frame_id="velodyne")
    transform.transform.translation.z = 1.7
    transform.transform.rotation.w = 1.0
    # The camera 0.1 m ahead of the LiDAR, looking along its x (optical z = LiDAR x, x = -y, y = -z).
    camera = TransformStamped(header=Header(stamp=rospy.Time(1000), frame_id="velodyne"), child_frame_id="camera")
    camera.transform.translation.x = 0.1
    camera.transform.rotation.x, camera.transform.rotation.y = -0.5, 0.5
    camera.transform.rotation.z, camera.transform.rotation.w = -0.5, 0.5
    bag.write("/tf_static", TFMessage(transforms=[transform, camera]), rospy.Time(1000))
