#!/usr/bin/python3
"""Independent check of a trajectory's crispness with Open3D (not ARTEMIS code): point-to-plane ICP
of scan B against scan A (KITTI raw drive 0013), started from the relative pose the trajectory
gives; prints how far ICP moves scan B. Crisp poses need a small correction.

  /usr/bin/python3 bench/pair_icp_open3d.py TRAJECTORY [TRAJECTORY ...] [--pairs 0:30,10:40]
Data: $ARTEMIS_DATA_DIR/kitti_raw (default ../shared/data/kitti_raw).
"""
import argparse
import os
import sys

import numpy as np
import open3d as o3d


def load_poses(path):
    rows = np.loadtxt(path).reshape(-1, 3, 4)
    poses = np.tile(np.eye(4), (len(rows), 1, 1))
    poses[:, :3, :] = rows
    return poses


def load_scan(drive, index):
    path = os.path.join(drive, "velodyne_points", "data", f"{index:010d}.bin")
    points = np.fromfile(path, dtype=np.float32).reshape(-1, 4)[:, :3].astype(np.float64)
    r = np.linalg.norm(points, axis=1)
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points[(r > 2.0) & (r < 70.0)]))
    cloud = cloud.voxel_down_sample(0.1)
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=0.6, max_nn=30))
    return cloud


def correction(scans, poses, a, b):
    relative = np.linalg.inv(poses[a]) @ poses[b]  # scan b into scan a's frame
    result = None
    current = relative
    for distance in (1.0, 0.5, 0.25):
        loss = o3d.pipelines.registration.TukeyLoss(k=distance / 2)
        method = o3d.pipelines.registration.TransformationEstimationPointToPlane(loss)
        result = o3d.pipelines.registration.registration_icp(
            scans[b], scans[a], distance, current, method,
            o3d.pipelines.registration.ICPConvergenceCriteria(1e-7, 1e-7, 100))
        current = result.transformation
    delta = np.linalg.inv(relative) @ current
    angle = np.degrees(np.arccos(np.clip((np.trace(delta[:3, :3]) - 1) / 2, -1, 1)))
    return np.linalg.norm(delta[:3, 3]), angle, result.fitness


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("trajectories", nargs="+")
    parser.add_argument("--pairs", default="0:30,10:40,19:49")
    args = parser.parse_args()
    data = os.environ.get("ARTEMIS_DATA_DIR") or "../shared/data"
    drive = os.path.join(data, "kitti_raw", "2011_09_26", "2011_09_26_drive_0013_sync")
    if not os.path.isdir(drive):
        sys.exit(f"{drive} not found: set ARTEMIS_DATA_DIR to the folder holding kitti_raw/")
    pairs = [tuple(int(x) for x in p.split(":")) for p in args.pairs.split(",")]
    scans = {i: load_scan(drive, i) for i in sorted({i for p in pairs for i in p})}
    for path in args.trajectories:
        poses = load_poses(path)
        for a, b in pairs:
            metres, degrees, fitness = correction(scans, poses, a, b)
            print(f"{path}: Open3D ICP of scan {b} against scan {a} corrects {100 * metres:.1f} cm, "
                  f"{degrees:.3f} deg (fitness {fitness:.2f})")


if __name__ == "__main__":
    main()
