#!/usr/bin/env bash
# Writes the seed corpus of every fuzz target into OUT/<target>/ (make fuzz: build-fuzz/seeds):
#   - small pieces of the real KITTI recordings in $ARTEMIS_DATA_DIR (default ../shared/data beside
#     the repository): a scan cut to a few hundred points, calibrations, OXTS packets, timestamps,
#     poses, tracking labels, SemanticKITTI labels. Nothing is copied into the repository.
#   - a short, small simulation (artemis sim: scans, labels, 8- and 16-bit PNGs, PLY, scene.json and
#     a run's config.json), when an artemis binary is found ($ARTEMIS_BIN, else build/bin/artemis,
#     build-ci/bin/artemis, build-fuzz/bin/artemis); skipped with a note otherwise.
#   - the repository's own JSON files (vocabulary, aliases, model configurations), and a few
#     hand-written inputs per format (so that every target has seeds without data or binary).
# Usage: fuzz/make_corpus.sh OUT
set -euo pipefail

out=${1:?usage: fuzz/make_corpus.sh OUT}
root=$(cd "$(dirname "$0")/.." && pwd)
data=${ARTEMIS_DATA_DIR:-$root/../shared/data}
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

targets=(fuzz_velodyne_scan fuzz_kitti_calib fuzz_kitti_oxts fuzz_kitti_poses fuzz_kitti_timestamps
         fuzz_semantic_labels fuzz_kitti_boxes fuzz_ply fuzz_png fuzz_mask_json fuzz_vocabulary
         fuzz_alias_table fuzz_dense_model fuzz_sim_config fuzz_run_config fuzz_ros_messages fuzz_camera_calib
         fuzz_rosbag_file)
for t in "${targets[@]}"; do rm -rf "${out:?}/$t"; mkdir -p "$out/$t"; done

# seed TARGET NAME FILE [BYTES]: FILE (its first BYTES bytes) as seed NAME of TARGET, if it exists.
seed() {
  local target=$1 name=$2 file=$3 bytes=${4:-}
  [[ -f $file ]] || { echo "make_corpus: no $file (skipped)" >&2; return 0; }
  if [[ -n $bytes ]]; then head -c "$bytes" "$file" >"$out/$target/$name"; else cp "$file" "$out/$target/$name"; fi
}
# text TARGET NAME: stdin as seed NAME of TARGET.
text() { cat >"$out/$1/$2"; }

# --- Real recordings -----------------------------------------------------------------------------
if [[ -d $data ]]; then
  raw=$data/kitti_raw/2011_09_26
  drive=$raw/2011_09_26_drive_0013_sync
  odo=$data/kitti_odometry
  sk=$data/semantickitti_fragment/sequences/00
  seed fuzz_velodyne_scan raw_300pts.bin "$drive/velodyne_points/data/0000000000.bin" $((300 * 16))
  seed fuzz_velodyne_scan odometry_200pts.bin "$odo/sequences/00/velodyne/000000.bin" $((200 * 16))
  seed fuzz_velodyne_scan semantickitti_50pts.bin "$sk/velodyne/000000.bin"
  for f in calib_cam_to_cam calib_velo_to_cam calib_imu_to_velo; do seed fuzz_kitti_calib "$f.txt" "$raw/$f.txt"; done
  seed fuzz_kitti_calib odometry_calib.txt "$odo/sequences/00/calib.txt"
  seed fuzz_kitti_oxts oxts_0.txt "$drive/oxts/data/0000000000.txt"
  seed fuzz_kitti_oxts oxts_49.txt "$drive/oxts/data/0000000049.txt"
  seed fuzz_kitti_timestamps velodyne_timestamps.txt "$drive/velodyne_points/timestamps.txt"
  seed fuzz_kitti_timestamps velodyne_timestamps_start.txt "$drive/velodyne_points/timestamps_start.txt"
  seed fuzz_kitti_timestamps oxts_timestamps.txt "$drive/oxts/timestamps.txt"
  seed fuzz_kitti_timestamps odometry_times.txt "$odo/sequences/00/times.txt"
  seed fuzz_kitti_poses odometry_poses.txt "$odo/poses/00.txt"
  [[ -f $data/kitti_raw/reference_poses.txt ]] &&
    head -n 10 "$data/kitti_raw/reference_poses.txt" | text fuzz_kitti_poses reference_poses_10.txt
  seed fuzz_kitti_boxes tracking_labels.txt "$data/kitti_raw/tracking_labels.txt"
  [[ -f $data/kitti_raw/tracking_labels.txt ]] &&
    head -n 12 "$data/kitti_raw/tracking_labels.txt" | text fuzz_kitti_boxes tracking_labels_12.txt
  seed fuzz_semantic_labels semantickitti_50.label "$sk/labels/000000.label"
else
  echo "make_corpus: no data folder $data (ARTEMIS_DATA_DIR): no seeds from real recordings" >&2
fi

# --- A small simulation --------------------------------------------------------------------------
bin=${ARTEMIS_BIN:-}
if [[ -z $bin ]]; then
  for b in "$root/build/bin/artemis" "$root/build-ci/bin/artemis" "$root/build-fuzz/bin/artemis"; do
    [[ -x $b ]] && { bin=$b; break; }
  done
fi
if [[ -n $bin && -x $bin ]]; then
  # Small images (64x20) and a coarse scan keep every file small; traffic gives moving labels.
  cat >"$work/params.json" <<'EOF'
{"frames": 2, "scene": {"seed": 3, "street_length_m": 50.0, "max_edge_m": 2.0},
 "lidar": {"azimuth_step_deg": 6.0}, "camera": {"width_px": 64, "height_px": 20},
 "traffic": {"cars_ahead": 1, "cars_behind": 1}}
EOF
  if "$bin" --log-level error sim --params "$work/params.json" -o "$work/sim" >/dev/null 2>"$work/sim.log"; then
    s=$work/sim
    seed fuzz_sim_config params_small.json "$work/params.json"
    seq=$s/sequences/00
    seed fuzz_velodyne_scan sim_300pts.bin "$seq/velodyne/000000.bin" $((300 * 16))
    seed fuzz_semantic_labels sim_300.label "$seq/labels/000000.label" $((300 * 4))
    seed fuzz_kitti_calib sim_calib.txt "$seq/calib.txt"
    seed fuzz_kitti_timestamps sim_times.txt "$seq/times.txt"
    seed fuzz_kitti_poses sim_poses.txt "$s/poses/00.txt"
    seed fuzz_png sim_rgb8.png "$seq/image_2/000000.png"
    for kind in depth_2 semantic_2 instance_2; do seed fuzz_png "sim_${kind}.png" "$s/gt/$kind/000000.png"; done
    seed fuzz_png sim_class_preview.png "$s/preview/000000_class.png"
    # The settings part of scene.json (its object list is large and adds nothing to the parser).
    sed -n '1,/^ },$/p' "$s/scene.json" | sed '$ s/},$/}}/' >"$work/scene_params.json"
    seed fuzz_sim_config scene_params.json "$work/scene_params.json"
    # A sparse reference cloud (binary PLY) of the simulated scans.
    if "$bin" --log-level error dataset export-cloud "$seq" --voxel 4 -o "$work/cloud.ply" >/dev/null 2>&1; then
      seed fuzz_ply sim_cloud.ply "$work/cloud.ply" 200000
    fi
    # A run over one frame: its config.json (and its mesh, when small).
    if timeout 120 "$bin" --log-level error run "$seq" --frames 0:1 --out "$work/run" >/dev/null 2>&1; then
      seed fuzz_run_config run_config.json "$work/run/config.json"
      [[ -f $work/run/mesh.ply && $(stat -c %s "$work/run/mesh.ply") -lt 200000 ]] &&
        seed fuzz_ply run_mesh.ply "$work/run/mesh.ply"
    fi
  else
    echo "make_corpus: artemis sim failed (see below): no simulated seeds" >&2
    cat "$work/sim.log" >&2
  fi
else
  echo "make_corpus: no artemis binary (ARTEMIS_BIN, build/bin/artemis): no simulated seeds" >&2
fi

# --- The repository's JSON files -------------------------------------------------------------------
seed fuzz_vocabulary semantickitti_vocabulary.json "$root/data/semantics/semantickitti_vocabulary.json"
seed fuzz_alias_table aliases.json "$root/data/semantics/aliases.json"
for m in "$root"/data/models/*.json; do seed fuzz_dense_model "$(basename "$m")" "$m"; done

# --- Hand-written inputs ---------------------------------------------------------------------------
printf '\x00\x00\x80\x3f\x00\x00\x00\x40\x00\x00\x40\x40\x00\x00\x00\x3f' >"$out/fuzz_velodyne_scan/one_point.bin"
printf '\x0a\x00\x01\x00\x28\x00\x00\x00\xfc\x00\x02\x00' >"$out/fuzz_semantic_labels/three.label"
text fuzz_kitti_calib rt.txt <<'EOF'
calib_time: 25-May-2012 16:47:16
R: 1 0 0 0 1 0 0 0 1
T: -8.086759e-01 3.195559e-01 -7.997231e-01
EOF
text fuzz_kitti_oxts oxts.txt <<'EOF'
49.011212804408 8.4228850417969 112.83492279053 0.022447 1e-05 -1.2219096732051 -3.3256321640686 1.1384311814592 3.5147680214713 0.037625160413037 -0.03878884255623 -0.29437452763793 0.037166856911681 9.9957015129717 -0.30581030960531 -0.19635662515203 9.9942128010936 -0.017332142869546 0.024792163815438 0.14511808479348 -0.017498934149631 0.021393359392165 0.14563031426063 0.49229361157748 0.068883960397178 4 10 4 4 0
EOF
text fuzz_kitti_poses identity.txt <<'EOF'
1 0 0 0 0 1 0 0 0 0 1 0
1 0 0 1.5 0 1 0 -0.25 0 0 1 0.01
EOF
text fuzz_kitti_timestamps raw.txt <<'EOF'
2011-09-26 13:02:25.964389445
2011-09-26 13:02:26.067999990
EOF
text fuzz_kitti_timestamps seconds.txt <<'EOF'
0.000000e+00
1.036000e-01
EOF
text fuzz_kitti_boxes tracking.txt <<'EOF'
0 0 Car 0 0 -1.79 296.74 161.75 455.23 292.55 2.00 1.82 4.43 -4.55 1.85 13.41 -2.11
0 -1 DontCare -1 -1 -10 219.31 188.49 245.50 218.56 -1000 -1000 -1000 -10 -1 -1 -1
2 1 Van 0 1 1.98 0 170.2 51.0 244.3 2.31 1.91 5.24 -14.4 2.17 15.01 1.05
EOF
text fuzz_kitti_boxes object.txt <<'EOF'
Pedestrian 0.00 0 -0.20 712.40 143.00 810.73 307.92 1.89 0.48 1.20 1.84 1.47 8.41 0.01
Car 0.00 2 1.85 387.63 181.54 423.81 203.12 1.67 1.87 3.69 -16.53 2.39 58.49 1.57 0.92
EOF
text fuzz_ply ascii_mesh.ply <<'EOF'
ply
format ascii 1.0
comment hand-written seed
element vertex 4
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
element face 2
property list uchar int vertex_indices
property ushort class_id
end_header
0 0 0 255 0 0
1 0 0 0 255 0
1 1 0 0 0 255
0 1 0.5 10 20 30
3 0 1 2 40
3 0 2 3 50
EOF
{
  printf 'ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n'
  printf 'element face 1\nproperty list uchar uint vertex_indices\nend_header\n'
  printf '\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x3f\x00\x00\x00\x00\x00\x00\x00\x00'
  printf '\x00\x00\x00\x00\x00\x00\x80\x3f\x00\x00\x00\x00\x03\x00\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00'
} >"$out/fuzz_ply/binary_le.ply"
{
  printf 'ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty double x\nproperty int y\nproperty char z\n'
  printf 'end_header\n'
  printf '\x3f\xf0\x00\x00\x00\x00\x00\x00\x00\x00\x00\x07\xff\xc0\x00\x00\x00\x00\x00\x00\x00\xff\xff\xff\xfe\x05'
} >"$out/fuzz_ply/binary_be.ply"
# A 1x1 8-bit grey PNG and a 2x1 16-bit grey one (values 7 and 256).
printf '\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x01\x00\x00\x00\x01\x08\x00\x00\x00\x00\x3a\x7e\x9b\x55\x00\x00\x00\x0a\x49\x44\x41\x54\x78\x9c\x63\x68\x00\x00\x00\x82\x00\x81\x77\xcd\x72\xb6\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82' \
  >"$out/fuzz_png/grey8_1x1.png"
printf '\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x02\x00\x00\x00\x01\x10\x00\x00\x00\x00\x81\xd9\xfc\x15\x00\x00\x00\x0d\x49\x44\x41\x54\x78\x9c\x63\x60\x60\x67\x64\x00\x00\x00\x1c\x00\x09\x46\x50\x78\x87\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82' \
  >"$out/fuzz_png/grey16_2x1.png"
text fuzz_mask_json masks.json <<'EOF'
{"masks": [{"id": 1, "class": "car", "score": 0.91},
           {"id": 2, "text": "road", "score": 0.62},
           {"id": 3, "class": "vegetation", "score": 1.0}]}
EOF
text fuzz_mask_json masks_unprompted.json <<'EOF'
{"masks": [{"id": 3, "class": "Traffic sign", "score": 0}, {"id": 1, "class": "car", "score": 0.5},
           {"id": 2, "class": "building", "score": 0.25}]}
EOF
text fuzz_vocabulary small.json <<'EOF'
{"classes": [{"id": 1, "name": "car", "rgb": [100, 150, 245], "labels": [10, 252]},
             {"id": 7, "name": "street lamp", "rgb": [0, 0, 0], "labels": [80]}]}
EOF
text fuzz_alias_table user_aliases.json <<'EOF'
{"extends_builtin": true, "comment": "hand-written seed",
 "stop_words": ["please"], "general_words": ["object"],
 "aliases": {"street lamp": "pole", "vehicle": ["car", "truck"]},
 "anchors": {"car": ["car.n.01"], "vegetation": ["plant.n.02", "02958343-n"]},
 "riders": {"bicyclist": ["person", "bicycle"]}, "riding_words": ["riding", "on"]}
EOF
text fuzz_dense_model small_model.json <<'EOF'
{"name": "tiny", "input": {"size_multiple": 4, "resize_width": 0, "scale": 0.5, "mean": [1, 2, 3],
 "channel_order": "bgr", "probe_size": [16, 8]}, "output": "probabilities",
 "labels": ["Road", "Car", "Truck", "Sky"],
 "classes": {"Road": "road", "Car": "car", "Truck": "truck", "Sky": null},
 "confusable": [["car", "truck"]]}
EOF
text fuzz_sim_config settings.json <<'EOF'
{"frames": 3, "scene": {"seed": 11, "street_length_m": 50.0}, "lidar": {"dropout": 0.1},
 "traffic": {"cars_ahead": 2, "walkers_per_100m": 3.0, "crossings": 1}}
EOF
text fuzz_run_config config.json <<'EOF'
{"dataset": {"path": "data/street/sequences/00", "format": "auto", "frames": "5:40",
             "vertical_correction": true, "poses": "recording"},
 "texture": {"holdout": 3}}
EOF
text fuzz_run_config config_all.json <<'EOF'
{"dataset": {"path": "/data/kitti_raw/2011_09_26", "frames": "all", "vertical_correction": false}}
EOF
text fuzz_run_config config_single.json <<'EOF'
{"dataset": {"frames": "7"}}
EOF

# --- ROS bags ------------------------------------------------------------------------------------
# The first message of each topic of the tests' bag (Debian's python3-rosbag writes it), when that
# Python is there; and hand-written ones.
if /usr/bin/python3 -c "import rosbag, sensor_msgs.msg, nav_msgs.msg, tf2_msgs.msg" 2>/dev/null; then
  /usr/bin/python3 "$root/tests/datasets/write_test_bag.py" "$work/seed.bag" none
  /usr/bin/python3 - "$work/seed.bag" "$out/fuzz_ros_messages" <<'PY'
import sys
import rosbag
seen = set()
for topic, raw, _ in rosbag.Bag(sys.argv[1]).read_messages(raw=True):
    if topic not in seen:
        seen.add(topic)
        open(sys.argv[2] + "/" + topic.strip("/").replace("/", "_") + ".msg", "wb").write(raw[1])
PY
  # Whole bags, small: three tiny clouds and a transform, in each chunk compression.
  /usr/bin/python3 - "$out/fuzz_rosbag_file" <<'PY'
import struct
import sys
import rosbag
import rospy
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import Header
from tf2_msgs.msg import TFMessage
from geometry_msgs.msg import TransformStamped
fields = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1) for i, n in enumerate("xyz")]
for compression in ("none", "bz2", "lz4"):
    with rosbag.Bag(sys.argv[1] + "/tiny_" + compression + ".bag", "w", compression=compression) as bag:
        t0 = rospy.Time(1000)
        tf = TransformStamped(header=Header(stamp=t0, frame_id="base_link"), child_frame_id="velodyne")
        tf.transform.rotation.w = 1.0
        bag.write("/tf_static", TFMessage(transforms=[tf]), t0)
        for k in range(3):
            t = t0 + rospy.Duration(0, k * 100_000_000)
            data = struct.pack("<6f", 1.0 + k, 2.0, 3.0, 4.0, 5.0, 6.0)
            bag.write("/points", PointCloud2(header=Header(seq=k, stamp=t, frame_id="velodyne"), height=1, width=2,
                                             fields=fields, point_step=12, row_step=24, data=data), t)
PY
else
  echo "make_corpus: /usr/bin/python3 cannot import rosbag (bag message seeds skipped)" >&2
fi
# A Livox CustomMsg: header (seq 7, 1000.5 s, frame "livox"), timebase, one point at (10, -1, 0.5).
printf '\x07\x00\x00\x00\xe8\x03\x00\x00\x00\x65\xcd\x1d\x05\x00\x00\x00livox\x00\xe1\xf5\x05\xe9\x00\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00\x00\x00\x00\x00\x00\x00\x20\x41\x00\x00\x80\xbf\x00\x00\x00\x3f\x28\x00\x01' \
  >"$out/fuzz_ros_messages/livox_custom.msg"
text fuzz_camera_calib avia.yaml <<'EOF'
# the public Livox Avia + camera rig
image_width: 1280
image_height: 1024
intrinsics: [1293.56944, 1293.3155, 626.91359, 522.799224]
distortion_model: radtan
distortion: [-0.0761587, 0.123001, -0.00113433, 0.000251384]
T_L_C: [0, 0, 1, 0.05, -1, 0, 0, 0.02, 0, -1, 0, -0.03]
time_offset_s: -0.1
EOF
text fuzz_camera_calib fisheye_4x4.yaml <<'EOF'
%YAML:1.0
image_width: 640
image_height: 480
intrinsics: [300, 300, 320, 240]
distortion_model: equidistant
distortion: [0.1, -0.01, 0.001, 0]
T_L_C: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
EOF

for t in "${targets[@]}"; do
  printf '%-24s %3d seeds %8d bytes\n' "$t" "$(find "$out/$t" -type f | wc -l)" "$(cat "$out/$t"/* | wc -c)"
done
