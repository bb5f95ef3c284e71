"""Plots memory_bench's memory.csv: resident memory and the time to map each frame (without
waiting for the simulator) over the drive.

usage: /usr/bin/python3 bench/plot_memory.py memory.csv memory.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    frames, rss, mapping, sim = [], [], [], []
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            frames.append(int(row["frame"]))
            rss.append(float(row["rss_mb"]))
            sim.append(float(row["sim_mb"]))
            mapping.append(float(row["total_ms"]) - float(row.get("read_ms") or 0.0))
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6), sharex=True, height_ratios=[2, 1])
    top.plot(frames, rss, color="tab:blue", label="whole process")
    top.plot(frames, sim, color="tab:gray", linestyle="--", label="before the run (the simulator's street)")
    top.legend(loc="lower right")
    top.set_ylabel("resident memory (MB)")
    top.set_ylim(bottom=0)
    top.grid(alpha=0.3)
    top.set_title("artemis run on the simulated street: memory over the drive")
    bottom.plot(frames, mapping, color="tab:gray", linewidth=0.5)
    bottom.set_yscale("log")  # the frames that finish tiles take seconds, the others tens of ms
    bottom.set_ylabel("mapping a frame (ms)")
    bottom.set_xlabel("frame")
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
