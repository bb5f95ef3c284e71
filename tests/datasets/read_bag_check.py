#!/usr/bin/env python3
"""Reads a bag with Debian's python3-rosbag and deserializes every message with the ROS message
classes (genpy, by the bag's own type names and MD5 sums), then prints one JSON object: per topic,
its type, count and a few values of its first message. The tests use it to check that bags written
by ARTEMIS are bags any ROS tool reads.

Usage: read_bag_check.py BAG
"""
import json
import struct
import sys

import rosbag


def first_values(msg):
    kind = msg._type
    if kind == "sensor_msgs/PointCloud2":
        fields = [f.name for f in msg.fields]
        x, y, z = struct.unpack_from("<fff", msg.data, 0)
        return {"fields": fields, "width": msg.width, "point_step": msg.point_step, "first": [x, y, z]}
    if kind == "sensor_msgs/Image":
        return {"encoding": msg.encoding, "width": msg.width, "height": msg.height, "first": list(msg.data[:3])}
    if kind == "sensor_msgs/CompressedImage":
        return {"format": msg.format, "bytes": len(msg.data)}
    if kind == "sensor_msgs/CameraInfo":
        return {"width": msg.width, "height": msg.height, "K": list(msg.K), "D": list(msg.D)}
    if kind == "nav_msgs/Odometry":
        p = msg.pose.pose.position
        return {"child_frame_id": msg.child_frame_id, "position": [p.x, p.y, p.z]}
    if kind == "sensor_msgs/Imu":
        a = msg.linear_acceleration
        return {"linear_acceleration": [a.x, a.y, a.z], "orientation_covariance0": msg.orientation_covariance[0]}
    if kind == "tf2_msgs/TFMessage":
        return {"children": [t.child_frame_id for t in msg.transforms]}
    return {}


def main():
    topics = {}
    with rosbag.Bag(sys.argv[1]) as bag:
        for topic, msg, t in bag.read_messages():
            entry = topics.setdefault(topic, {"type": msg._type, "count": 0, "stamp": msg.header.stamp.to_sec()
                                              if hasattr(msg, "header") else t.to_sec()})
            if entry["count"] == 0:
                entry["first"] = first_values(msg)
            entry["count"] += 1
    print(json.dumps(topics))


if __name__ == "__main__":
    main()
