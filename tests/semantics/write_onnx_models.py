#!/usr/bin/python3
"""Small ONNX models for the ONNX segmenter's tests, written with Debian's python3-onnx.

    write_onnx_models.py OUT_DIR

Writes into OUT_DIR:
  add_one.onnx        x [1, 3] float -> y = x + 1
  yolo_dense.onnx     a YOLO-seg graph (outputs [1, 4+nc+nm, N] and prototypes [1, nm, 32, 32],
                      prototypes first) with hand-set detections on a 128 x 128 input
  yolo_e2e.onnx       the same detections in the end-to-end layout [1, K, 6+nm]
  yolo_dense_t.onnx   the dense layout transposed, [1, N, 4+nc+nm]
  yolo_hostile.onnx   end-to-end rows no model should give (NaN, 1e30, a class index of no label, an
                      empty box) around one good detection
  everything.onnx     "segment everything" (one class) for three colour blobs on a 128 x 128 input
  clip_image.onnx     a toy CLIP image encoder: the mean of each normalised channel, [batch, 3]
  clip_text.onnx      a toy CLIP text encoder: token embeddings summed up to the end token
  clip_merges.txt     the toy CLIP tokenizer's merges
  class_colours.onnx  instance segmentation of colour-coded class images: one detection per colour,
                      its prototype the pixels of that colour (the end-to-end plumbing test)
  class_colours.json  the colours and labels of class_colours.onnx
Every detection's numbers are documented where they are set; the C++ tests check against them.
"""
import json
import os
import sys

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

OPSET = 13


def save(graph, path):
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", OPSET)], producer_name="artemis-tests")
    model.ir_version = 8
    onnx.checker.check_model(model)
    onnx.save(model, path)


def constant_outputs(inputs, outputs):
    """A graph that returns constant tensors (name -> array) whatever its image input."""
    nodes, outs = [], []
    for name, value in outputs:
        nodes.append(helper.make_node("Constant", [], [name], value=numpy_helper.from_array(value.astype(np.float32))))
        outs.append(helper.make_tensor_value_info(name, TensorProto.FLOAT, list(value.shape)))
    return nodes, outs


def disc(size, cx, cy, r):
    """+1 inside the disc (proto pixels), -1 outside."""
    y, x = np.mgrid[0:size, 0:size]
    return np.where((x + 0.5 - cx) ** 2 + (y + 0.5 - cy) ** 2 <= r * r, 1.0, -1.0)


def write_add_one(out):
    x = helper.make_tensor_value_info("x", TensorProto.FLOAT, [1, 3])
    y = helper.make_tensor_value_info("y", TensorProto.FLOAT, [1, 3])
    one = helper.make_node("Constant", [], ["one"], value=numpy_helper.from_array(np.ones([1, 3], np.float32)))
    add = helper.make_node("Add", ["x", "one"], ["y"])
    save(helper.make_graph([one, add], "add_one", [x], [y]), os.path.join(out, "add_one.onnx"))


# The hand-set detections on a 128 x 128 input (labels: 0 car, 1 person; 4 prototypes at 32 x 32,
# a quarter of the input). Boxes as centre x, y, width, height in input pixels.
#   0: car 0.9 at (40, 40), 40 x 40; its mask the disc of radius 20 there (prototype 0)
#   1: car 0.8 at (44, 42), 40 x 40: overlaps 0 (IoU 0.75), suppressed (prototype 1)
#   2: person 0.7 at (100, 100), 30 x 30; its mask the disc of radius 12 there (prototype 2)
#   3: car 0.1: below any sensible threshold
DETECTIONS = [
    (40, 40, 40, 40, 0, 0.9, 0),
    (44, 42, 40, 40, 0, 0.8, 1),
    (100, 100, 30, 30, 1, 0.7, 2),
    (70, 20, 10, 10, 0, 0.1, 3),
]


def prototypes():
    p = np.full([1, 4, 32, 32], -1.0)
    p[0, 0] = disc(32, 10, 10, 5)
    p[0, 1] = disc(32, 11, 10.5, 5)
    p[0, 2] = disc(32, 25, 25, 3)
    p[0, 3] = disc(32, 17.5, 5, 1)
    return p


def coefficients(proto):
    c = np.zeros(4)
    c[proto] = 8.0  # sigmoid(8 * +-1): 0.9997 inside, 0.0003 outside
    return c


def write_yolo(out):
    image = helper.make_tensor_value_info("images", TensorProto.FLOAT, [1, 3, 128, 128])
    dense = np.zeros([1, 4 + 2 + 4, len(DETECTIONS)])
    e2e = np.zeros([1, len(DETECTIONS), 6 + 4])
    for i, (cx, cy, w, h, label, score, proto) in enumerate(DETECTIONS):
        dense[0, 0:4, i] = [cx, cy, w, h]
        dense[0, 4 + label, i] = score
        dense[0, 4 + (1 - label), i] = 0.05
        dense[0, 6:10, i] = coefficients(proto)
        e2e[0, i, 0:6] = [cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2, score, label]
        e2e[0, i, 6:10] = coefficients(proto)
    # The end-to-end layout arrives already suppressed: detection 1 is left out there.
    e2e = np.delete(e2e, 1, axis=1)
    nodes, outs = constant_outputs([image], [("protos", prototypes()), ("output0", dense)])
    save(helper.make_graph(nodes, "yolo_dense", [image], outs), os.path.join(out, "yolo_dense.onnx"))
    nodes, outs = constant_outputs([image], [("output0", e2e), ("protos", prototypes())])
    save(helper.make_graph(nodes, "yolo_e2e", [image], outs), os.path.join(out, "yolo_e2e.onnx"))
    nodes, outs = constant_outputs([image], [("output0", np.transpose(dense, (0, 2, 1))), ("protos", prototypes())])
    save(helper.make_graph(nodes, "yolo_dense_t", [image], outs), os.path.join(out, "yolo_dense_t.onnx"))
    good = e2e[0, 0]
    bad = np.zeros([6, 10])
    bad[0] = good
    bad[0, 0] = np.nan
    bad[1] = good
    bad[1, 2] = 1e30
    bad[2] = good
    bad[2, 5] = 7  # no label 7
    bad[3] = good
    bad[3, 5] = np.nan
    bad[4] = good
    bad[4, 0], bad[4, 2] = bad[4, 2], bad[4, 0]  # x1 < x0
    bad[5] = good
    bad[5, 6] = np.inf
    hostile = np.concatenate([bad, good[None]], axis=0)[None]
    nodes, outs = constant_outputs([image], [("output0", hostile), ("protos", prototypes())])
    save(helper.make_graph(nodes, "yolo_hostile", [image], outs), os.path.join(out, "yolo_hostile.onnx"))


# Three blobs on a 128 x 128 image (the test paints them): red at (32, 32), green at (96, 32), blue
# at (64, 96), each a disc of radius 16. One class ("object"), one prototype each.
BLOBS = [(32, 32), (96, 32), (64, 96)]


def write_everything(out):
    image = helper.make_tensor_value_info("images", TensorProto.FLOAT, [1, 3, 128, 128])
    dense = np.zeros([1, 4 + 1 + 4, len(BLOBS)])
    p = np.full([1, 4, 32, 32], -1.0)
    for i, (cx, cy) in enumerate(BLOBS):
        dense[0, 0:4, i] = [cx, cy, 34, 34]
        dense[0, 4, i] = 0.9 - 0.1 * i
        dense[0, 5:9, i] = coefficients(i)
        p[0, i] = disc(32, cx / 4, cy / 4, 4)
    nodes, outs = constant_outputs([image], [("output0", dense), ("output1", p)])
    save(helper.make_graph(nodes, "everything", [image], outs), os.path.join(out, "everything.onnx"))


def write_clip_image(out):
    x = helper.make_tensor_value_info("pixel_values", TensorProto.FLOAT, ["batch", 3, 224, 224])
    y = helper.make_tensor_value_info("image_embeds", TensorProto.FLOAT, ["batch", 3])
    mean = helper.make_node("ReduceMean", ["pixel_values"], ["mean"], axes=[2, 3], keepdims=0)
    w = helper.make_node("Constant", [], ["w"], value=numpy_helper.from_array(np.eye(3, dtype=np.float32)))
    mm = helper.make_node("MatMul", ["mean", "w"], ["image_embeds"])
    save(helper.make_graph([mean, w, mm], "clip_image", [x], [y]), os.path.join(out, "clip_image.onnx"))


# The toy tokenizer: CLIP's byte-level BPE with these merges (after the version line). Words of
# the tests' prompts become single tokens ("g r" before "r e", or "green" would keep "re").
MERGES = ["g r", "gr e", "gre e", "gree n</w>", "r e", "re d</w>", "b l", "bl u", "blu e</w>", "t h", "th i",
          "thi n", "thin g", "thing s</w>"]


def bytes_to_unicode():
    bs = list(range(ord("!"), ord("~") + 1)) + list(range(ord("¡"), ord("¬") + 1)) + list(range(ord("®"), ord("ÿ") + 1))
    cs = bs[:]
    n = 0
    for b in range(256):
        if b not in bs:
            bs.append(b)
            cs.append(256 + n)
            n += 1
    return [chr(c) for c in cs], bs


def toy_vocab():
    chars, order = bytes_to_unicode()
    vocab = list(chars) + [c + "</w>" for c in chars] + ["".join(m.split()) for m in MERGES]
    vocab += ["<|startoftext|>", "<|endoftext|>"]
    return {t: i for i, t in enumerate(vocab)}


def write_clip_text(out):
    vocab = toy_vocab()
    table = np.zeros([len(vocab), 3], np.float32)
    table[vocab["red</w>"]] = [1, 0, 0]
    table[vocab["green</w>"]] = [0, 1, 0]
    table[vocab["blue</w>"]] = [0, 0, 1]
    # The background prompt, "things": a grey direction.
    table[vocab["things</w>"]] = [0.4, 0.4, 0.4]
    ids = helper.make_tensor_value_info("input_ids", TensorProto.INT64, [1, 77])
    y = helper.make_tensor_value_info("text_embeds", TensorProto.FLOAT, [1, 3])
    nodes = [
        helper.make_node("Constant", [], ["table"], value=numpy_helper.from_array(table)),
        helper.make_node("Gather", ["table", "input_ids"], ["embedded"], axis=0),  # [1, 77, 3]
        helper.make_node("Constant", [], ["seq_axis"], value=numpy_helper.from_array(np.array(1, np.int64))),
        helper.make_node("CumSum", ["embedded", "seq_axis"], ["summed"]),
        helper.make_node("ArgMax", ["input_ids"], ["end"], axis=1, keepdims=0),  # [1]: the end token, the largest id
        helper.make_node("Gather", ["summed", "end"], ["pooled"], axis=1),  # [1, 1, 3]
        helper.make_node("Constant", [], ["shape"], value=numpy_helper.from_array(np.array([1, 3], np.int64))),
        helper.make_node("Reshape", ["pooled", "shape"], ["text_embeds"]),
    ]
    save(helper.make_graph(nodes, "clip_text", [ids], [y]), os.path.join(out, "clip_text.onnx"))
    with open(os.path.join(out, "clip_merges.txt"), "w", encoding="utf-8") as f:
        f.write("#version: 0.2\n" + "\n".join(MERGES) + "\n")


# Colour-coded class images for the end-to-end test: each listed class a colour; the model's
# prototype k is the pixels within 40 (of 255, summed over channels) of colour k; detection k covers
# the whole input with score 1 (as the simulated segmenter's exact masks) and selects prototype k.
# Input 1242 x 375, as KITTI's camera.
CLASS_COLOURS = [
    ("car", [255, 0, 0]), ("road", [128, 64, 128]), ("sidewalk", [244, 35, 232]), ("building", [70, 70, 70]),
    ("vegetation", [107, 142, 35]), ("terrain", [152, 251, 152]), ("pole", [153, 153, 153]),
    ("traffic-sign", [220, 220, 0]), ("fence", [190, 153, 153]), ("person", [220, 20, 60]),
    ("bicycle", [119, 11, 32]), ("truck", [0, 0, 70]), ("parking", [250, 170, 160]),
    ("other-ground", [81, 0, 81]), ("trunk", [150, 100, 100]), ("bicyclist", [0, 0, 230]),
    ("motorcycle", [0, 80, 100]), ("other-vehicle", [0, 60, 100]), ("motorcyclist", [255, 255, 0]),
]


def write_class_colours(out):
    w, h = 1242, 375
    k = len(CLASS_COLOURS)
    image = helper.make_tensor_value_info("images", TensorProto.FLOAT, [1, 3, h, w])
    colours = np.array([c for _, c in CLASS_COLOURS], np.float32).reshape(1, k, 3, 1, 1) / 255.0
    dense = np.zeros([1, 4 + k + 32, k], np.float32)
    for i in range(k):
        dense[0, 0:4, i] = [w / 2, h / 2, w, h]
        dense[0, 4 + i, i] = 1.0
        dense[0, 4 + k + i, i] = 1.0
    nodes = [
        helper.make_node("Constant", [], ["colours"], value=numpy_helper.from_array(colours)),
        helper.make_node("Unsqueeze", ["images", "one"], ["expanded"]),  # [1, 1, 3, h, w]
        helper.make_node("Sub", ["expanded", "colours"], ["diff"]),  # [1, k, 3, h, w]
        helper.make_node("Abs", ["diff"], ["adiff"]),
        helper.make_node("ReduceSum", ["adiff", "two"], ["distance"], keepdims=0),  # [1, k, h, w]
        helper.make_node("Sub", ["limit", "distance"], ["within"]),  # > 0 within the limit
        helper.make_node("Mul", ["within", "gain"], ["logits"]),
        helper.make_node("Pad", ["logits", "pads", "minus"], ["output1"]),  # [1, 32, h, w]
        helper.make_node("Constant", [], ["output0"], value=numpy_helper.from_array(dense)),
    ]
    inits = [
        numpy_helper.from_array(np.array([1], np.int64), "one"),
        numpy_helper.from_array(np.array([2], np.int64), "two"),
        numpy_helper.from_array(np.array(40.0 / 255.0, np.float32), "limit"),
        numpy_helper.from_array(np.array(100.0, np.float32), "gain"),
        numpy_helper.from_array(np.array([0, 0, 0, 0, 0, 32 - k, 0, 0], np.int64), "pads"),
        numpy_helper.from_array(np.array(-10.0, np.float32), "minus"),
    ]
    outs = [helper.make_tensor_value_info("output0", TensorProto.FLOAT, [1, 4 + k + 32, k]),
            helper.make_tensor_value_info("output1", TensorProto.FLOAT, [1, 32, h, w])]
    save(helper.make_graph(nodes, "class_colours", [image], outs, initializer=inits),
         os.path.join(out, "class_colours.onnx"))
    with open(os.path.join(out, "class_colours.json"), "w") as f:
        json.dump({"labels": [n for n, _ in CLASS_COLOURS], "colours": [c for _, c in CLASS_COLOURS]}, f)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    write_add_one(out)
    write_yolo(out)
    write_everything(out)
    write_clip_image(out)
    write_clip_text(out)
    write_class_colours(out)


if __name__ == "__main__":
    main()
