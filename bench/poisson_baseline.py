#!/usr/bin/python3
"""The paper's "Poi" baseline (Table I): screened Poisson reconstruction of an aggregated LiDAR cloud.

Uses Debian's Open3D (python3-open3d 0.16): run it with /usr/bin/python3, not a python3 from a
virtual environment.

    /usr/bin/python3 bench/poisson_baseline.py --cloud ref.ply --trajectory trajectory.txt \\
        --out poisson.ply [--depth 10] [--density-quantile 0.02]

Steps, each timed:
  1. read the world-frame cloud (x, y, z; other vertex properties are ignored), e.g. from
     `artemis dataset export-cloud`;
  2. estimate normals from the neighbourhood (hybrid radius / k-nearest search);
  3. orient each normal towards the nearest trajectory position (the sensor that most likely saw
     the point; TRAJECTORY holds one row-major 3x4 T_W_L per line, 12 numbers);
  4. Poisson reconstruction at --depth;
  5. standard density trimming: remove the vertices whose Poisson density (the sample support
     of the octree node) is below the --density-quantile quantile;
  6. write a binary little-endian PLY with float x y z and int vertex_indices faces, which
     `artemis eval mesh` scores like any mesh.

Prints the figures, and with --json FILE also writes them as JSON.
"""

import argparse
import json
import sys
import time

import numpy as np
import open3d as o3d


def read_trajectory(path):
    """Sensor positions (N x 3) from a file of row-major 3x4 poses, 12 numbers a line."""
    rows = []
    with open(path, encoding="utf-8") as f:
        for line_no, line in enumerate(f, start=1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            values = line.split()
            if len(values) != 12:
                raise ValueError(f"{path} line {line_no}: expected 12 numbers, found {len(values)}")
            try:
                rows.append([float(v) for v in values])
            except ValueError as e:
                raise ValueError(f"{path} line {line_no}: {e}") from e
    if not rows:
        raise ValueError(f"{path}: no pose")
    poses = np.asarray(rows).reshape(-1, 3, 4)
    return poses[:, :, 3]


def nearest_positions(points, positions, chunk=200_000):
    """For each point, the nearest of the (few) trajectory positions, by brute force in chunks."""
    out = np.empty_like(points)
    pos_sq = np.einsum("ij,ij->i", positions, positions)
    for begin in range(0, len(points), chunk):
        p = points[begin:begin + chunk]
        # |p - c|^2 = |p|^2 - 2 p.c + |c|^2; |p|^2 is the same for every c.
        d = pos_sq[None, :] - 2.0 * p @ positions.T
        out[begin:begin + chunk] = positions[np.argmin(d, axis=1)]
    return out


def write_binary_ply(path, vertices, triangles):
    """Binary little-endian PLY: float x y z, faces as 'list uchar int vertex_indices'."""
    vertices = np.ascontiguousarray(vertices, dtype="<f4")
    faces = np.empty(len(triangles), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    faces["n"] = 3
    faces["v"] = triangles
    header = (
        "ply\n"
        "format binary_little_endian 1.0\n"
        "comment artemis bench/poisson_baseline.py (Open3D screened Poisson)\n"
        f"element vertex {len(vertices)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\n"
        "property list uchar int vertex_indices\n"
        "end_header\n"
    )
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(vertices.tobytes())
        f.write(faces.tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cloud", required=True, help="aggregated world-frame LiDAR cloud (PLY)")
    parser.add_argument("--trajectory", required=True, help="T_W_L poses, 12 numbers a line (row-major 3x4)")
    parser.add_argument("--out", required=True, help="output mesh (binary PLY)")
    parser.add_argument("--depth", type=int, default=10, help="Poisson octree depth (default 10)")
    parser.add_argument("--density-quantile", type=float, default=0.02,
                        help="remove vertices below this quantile of the Poisson density (default 0.02; 0 keeps all)")
    parser.add_argument("--normal-radius", type=float, default=0.5,
                        help="normal estimation: neighbourhood radius in m (default 0.5)")
    parser.add_argument("--normal-nn", type=int, default=30,
                        help="normal estimation: at most this many neighbours (default 30)")
    parser.add_argument("--threads", type=int, default=-1, help="Poisson threads (default: all)")
    parser.add_argument("--json", help="also write the figures to this JSON file")
    args = parser.parse_args()
    if not 0.0 <= args.density_quantile < 1.0:
        parser.error(f"--density-quantile must be in [0, 1), got {args.density_quantile}")
    if args.depth < 1:
        parser.error(f"--depth must be >= 1, got {args.depth}")

    figures = {"cloud": args.cloud, "trajectory": args.trajectory, "out": args.out, "depth": args.depth,
               "density_quantile": args.density_quantile, "normal_radius_m": args.normal_radius,
               "normal_nn": args.normal_nn, "seconds": {}}
    seconds = figures["seconds"]
    start = time.perf_counter()

    def lap(name, since):
        seconds[name] = round(time.perf_counter() - since, 3)
        return time.perf_counter()

    t = time.perf_counter()
    try:
        positions = read_trajectory(args.trajectory)
    except (OSError, ValueError) as e:
        print(f"poisson_baseline: {e}", file=sys.stderr)
        return 1
    cloud = o3d.io.read_point_cloud(args.cloud)
    points = np.asarray(cloud.points)
    if len(points) == 0:
        print(f"poisson_baseline: {args.cloud}: no points (missing or unreadable file?)", file=sys.stderr)
        return 1
    finite = np.isfinite(points).all(axis=1)
    if not finite.all():
        cloud = cloud.select_by_index(np.flatnonzero(finite))
        points = np.asarray(cloud.points)
    figures["cloud_points"] = len(points)
    figures["poses"] = len(positions)
    t = lap("read", t)

    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=args.normal_radius, max_nn=args.normal_nn))
    t = lap("normals", t)

    # Orient towards the sensor: flip the normals that point away from the nearest pose.
    normals = np.asarray(cloud.normals)
    to_sensor = nearest_positions(points, positions) - points
    flip = np.einsum("ij,ij->i", normals, to_sensor) < 0.0
    normals[flip] *= -1.0
    cloud.normals = o3d.utility.Vector3dVector(normals)
    t = lap("orient", t)

    mesh, densities = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(
        cloud, depth=args.depth, n_threads=args.threads)
    densities = np.asarray(densities)
    figures["poisson_vertices"] = len(mesh.vertices)
    figures["poisson_triangles"] = len(mesh.triangles)
    t = lap("poisson", t)

    if args.density_quantile > 0.0 and len(densities) > 0:
        threshold = float(np.quantile(densities, args.density_quantile))
        mesh.remove_vertices_by_mask(densities < threshold)
        figures["density_threshold"] = threshold
    figures["vertices"] = len(mesh.vertices)
    figures["triangles"] = len(mesh.triangles)
    t = lap("trim", t)

    if len(mesh.triangles) == 0:
        print("poisson_baseline: the reconstruction has no triangles; nothing written", file=sys.stderr)
        return 1
    try:
        write_binary_ply(args.out, np.asarray(mesh.vertices), np.asarray(mesh.triangles))
    except OSError as e:
        print(f"poisson_baseline: {args.out}: {e}", file=sys.stderr)
        return 1
    lap("write", t)
    seconds["total"] = round(time.perf_counter() - start, 3)
    # The reconstruction proper, as Table I times it: normals, orientation, Poisson, trimming.
    seconds["reconstruction"] = round(sum(seconds[k] for k in ("normals", "orient", "poisson", "trim")), 3)

    print(f"cloud       {args.cloud}: {figures['cloud_points']} points, {figures['poses']} poses")
    print(f"poisson     depth {args.depth}: {figures['poisson_vertices']} vertices, "
          f"{figures['poisson_triangles']} triangles")
    print(f"trimmed     density quantile {args.density_quantile}: {figures['vertices']} vertices, "
          f"{figures['triangles']} triangles -> {args.out}")
    print("seconds     " + "  ".join(f"{k} {v:.2f}" for k, v in seconds.items()))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(figures, f, indent=2)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
