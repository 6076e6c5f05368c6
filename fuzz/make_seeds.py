#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz targets (fuzz/corpus/<target>/).

A handful of small valid inputs per target, in the byte layouts the targets document at their top:
stream frames and replies, command sessions for the simulated Create, rig and scene files, recipes
for decoder images, point clouds. Run it again after changing a layout; the output is deterministic.
Reproducers of fixed findings are added next to these by hand (named after the finding).
"""
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
CORPUS = os.path.join(HERE, "corpus")


def write(target, name, data):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(bytes(data))


# --- create_driver: Open Interface bytes -------------------------------------------------------

SIZES = {7: 1, 13: 1, 19: 2, 20: 2, 29: 2, 35: 1, 43: 2, 44: 2}


def frame(packets):
    """[19][n][id data...][checksum] for (id, data bytes) pairs."""
    payload = []
    for pid, data in packets:
        payload += [pid] + list(data)
    body = [19, len(payload)] + payload
    return body + [(256 - sum(body) % 256) % 256]


def oi_parsers():
    ids = [7, 19, 20]
    f1 = frame([(7, [0]), (19, [0, 12]), (20, [0xFF, 0xFE])])
    f2 = frame([(7, [1]), (19, [0xFF, 0xF0]), (20, [0, 3])])
    write("oi_parsers", "create1_distance_angle", [0, len(ids)] + ids + f1 + f2)
    # The OI spec's stream example, expected ids on.
    write("oi_parsers", "spec_example_expected", [2, 2, 29, 13, 19, 5, 29, 2, 25, 13, 0, 163])
    # Noise with false headers (19 in the data) before a frame; Create 2 encoders.
    f3 = frame([(43, [1, 2]), (44, [3, 4]), (35, [2])])
    write("oi_parsers", "create2_noise_then_frame", [1, 3, 43, 44, 35, 5, 19, 19, 2, 0, 19, 200] + f3 + f3[:5])
    # A reply to Sensors group 6 (52 bytes) of a Create, then the next bytes.
    write("oi_parsers", "reply_group6", [0, 1, 6] + list(range(52)) + [19, 3])
    # Group 100 of a Create 2 (80 data bytes) as a frame.
    f4 = frame([(100, [i % 7 for i in range(80)])])
    write("oi_parsers", "create2_group100", [3, 1, 100] + f4)


def sim_robot():
    def send(*cmd):
        assert 1 <= len(cmd) <= 128
        return [len(cmd) - 1] + list(cmd)

    def step(ms):  # 10..640 ms
        return [0x80 | (ms // 10 - 1)]

    def op(code, value):
        return [0xC0 | code, value]

    drive = send(137, 0, 200, 0x80, 0x00)  # 200 mm/s straight
    write("sim_robot", "create1_stream_drive",
          [0] + send(128, 131) + send(148, 3, 7, 19, 20) + drive + step(500) + step(500) +
          send(142, 6) + send(149, 2, 19, 20) + op(0, 1) + step(200) + send(150, 0) + step(100) + send(150, 1) +
          step(100) + send(137, 0, 0, 0, 0) + step(50))
    # A script with a drive and a wait, played twice; a script that plays itself (refused inside).
    write("sim_robot", "create1_script_wait",
          [0] + send(128, 132, 152, 7, 137, 0, 100, 0x80, 0, 155, 5, 153) + step(640) + send(153) + step(640) +
          send(154) + send(152, 2, 153, 153, 153) + step(100) + send(156, 0, 50) + send(142, 19) + step(640) +
          send(157, 0, 90) + send(145, 0, 100, 0xFF, 0x9C) + step(640))
    # Create 2: full mode, drive direct and PWM, encoders streamed, LEDs and a song, OI stop.
    write("sim_robot", "create2_full_stream",
          [1] + send(128, 132, 145, 0, 100, 0, 120) + send(148, 2, 43, 44) + step(300) +
          send(146, 0, 50, 0, 50) + send(139, 0, 0, 0) + send(140, 0, 2, 60, 16, 62, 16) + send(141, 0) +
          op(4, 3) + step(100) + send(173) + step(50))
    # Safe mode: a cliff while driving falls back to Passive; events and wheel drops.
    write("sim_robot", "create1_safety_events",
          [2] + send(128, 131) + drive + step(100) + op(1, 2) + step(50) + send(131) + op(1, 0) +
          send(158, 5) + step(100) + op(0, 2) + step(50) + op(2, 4) + send(131) + drive + step(50) + op(6, 0) +
          send(128) + op(10, 3))
    # Baud 9600 shrinks the stream slot: a large stream request is refused.
    write("sim_robot", "create1_baud_stream_refused",
          [0] + send(128, 131, 129, 5) + send(148, 1, 6) + step(100) + send(129, 10) + send(148, 1, 6) + step(100))


# --- sl_rig / sl_sim: rig and scene files ---------------------------------------------

SMALL_RIG = """format_version: 1
# A 256 x 192 crop of the default camera (same lens): the middle of the default pattern.
camera:
  width: 256
  height: 192
  K: [1492.0, 0.0, 128.0, 0.0, 1492.0, 96.0, 0.0, 0.0, 1.0]
  D: [-0.08, 0.12, 0.0005, -0.0003, 0.0]
projector:
  width: 480
  height: 320
  K: [753.0, 0.0, 203.0, 0.0, 781.0, -38.0, 0.0, 0.0, 1.0]
  D: [0.02, 0.0, 0.0, 0.0, 0.0]
projector_pose:
  rotation: [0.994001447, -0.0269034905, -0.106006253,
             0.00609582126, 0.981393601, -0.191909984,
             0.109196907, 0.190112606, 0.975670658]
  translation: [0.05524, -0.00398, 0.01156]
pattern:
  rows: {rows}
  cols: {cols}
  primitive_width: 5
  primitive_height: 9
  gap_x: 2
  gap_y: 6
  offset_x: {offset_x}
  offset_y: {offset_y}
  flip_x: {flip}
  flip_y: {flip}
mount:
  parent_frame: platform_edge
  xyz: [-0.030, 0.025, 0.0865]
  rpy: [0.0, 0.0, -0.03702]
"""


def tables(rows, cols):
    n = rows * cols
    a = ", ".join("0.5" if i % 5 else ".nan" for i in range(n))
    b = ", ".join("0.0004" for _ in range(n))
    c = ", ".join("0.0001" for _ in range(n))
    rms = ", ".join("0.001" for _ in range(n))
    return ("depth_tables:\n  distances: [0.5, 0.7, 0.9]\n"
            "  linear: {a: [%s], b: [%s], rms: [%s]}\n"
            "  rational: {a: [%s], b: [%s], c: [%s], rms: [%s]}\n") % (a, b, rms, a, b, c, rms)


def rigs():
    small = SMALL_RIG.format(rows=16, cols=64, offset_x=0, offset_y=0, flip="false")
    sub = SMALL_RIG.format(rows=6, cols=20, offset_x=170, offset_y=80, flip="false")
    flipped = SMALL_RIG.format(rows=6, cols=20, offset_x=170, offset_y=80, flip="true")
    with open(os.path.join(ROOT, "sl_projector", "config", "default_rig.yaml")) as f:
        default = f.read()
    for target in ("rig_parser", "decoder_rig"):
        write(target, "small_rig.yaml", small)
        write(target, "small_rig_sub_pattern.yaml", sub)
        write(target, "small_rig_flipped_tables.yaml", flipped + tables(6, 20))
    write("rig_parser", "default_rig.yaml", default)


def scenes():
    for name in ("table_leg_20mm.yaml", "checkerboard_600.yaml", "three_planes.yaml", "shiny_bin_586.yaml"):
        shutil.copy(os.path.join(ROOT, "sl_sim", "scenes", name), os.path.join(CORPUS, "scene_parser", name))


# --- sl_decoder: image recipes (decoder_image_fuzz.cpp) ----------------------------------------

def header(flags, depth_m, tilt_x=0.0, tilt_y=0.0, gain=180.0, background=15):
    def byte(v, lo, hi):
        return max(0, min(255, round((v - lo) / (hi - lo) * 255)))

    return [flags, byte(depth_m, 0.2, 2.7), byte(tilt_x, -1, 1), byte(tilt_y, -1, 1), byte(gain, 0, 510), background]


def patch(op, x, y, pixels):
    h, w = len(pixels), len(pixels[0])
    out = [op] + list(struct.pack("<HH", x, y)) + [w - 1, h - 1]
    for row in pixels:
        out += row
    return out


def decoder_images():
    write("decoder_image", "plane_700mm", header(1, 0.7))
    write("decoder_image", "plane_450mm_noise", header(3, 0.45, gain=150))
    black = [[0] * 24 for _ in range(16)]
    bright = [[250] * 6 for _ in range(10)]
    write("decoder_image", "plane_occluded",
          header(1, 0.9, tilt_x=0.3) + patch(0, 300, 200, black) + patch(1, 100, 50, bright))
    write("decoder_image", "floor_slant", header(1, 1.2, tilt_y=0.7, gain=300))
    # No plane: one primitive-like blob (a Wide-Left-Right "Z") tiled over the whole image.
    tile = [[0] * 12 for _ in range(20)]
    for y in range(3, 18):
        for x in range(3, 9):
            band = (y - 3) // 5
            if band == 0 or (band == 1 and x <= 6) or (band == 2 and x >= 6):
                tile[y][x] = 200
    write("decoder_image", "tiled_primitive", header(0, 0.7, background=10) + patch(3, 0, 0, tile))


# --- sl_obstacle: clouds (cloud_conversion_fuzz.cpp) -------------------------------------------

FLOAT32, FLOAT64, UINT8 = 7, 8, 2
NAMES = ["x", "y", "z", "confidence", "sx", "sy", "sz", "state", "intensity"]


def cloud(fields, width, height, point_step, row_step, data, transform=(0, 0, 0, 64, 0, 0, 0)):
    out = [len(fields)]
    for name, datatype, offset in fields:
        out += [NAMES.index(name), datatype] + list(struct.pack("<I", offset)) + [1]
    out += list(struct.pack("<IIII", width, height, point_step, row_step)) + [0]
    out += [v & 0xFF for v in transform]
    return out + list(data)


def clouds():
    pts = [(0.5, 0.0, 0.1, 0.9), (0.6, -0.1, 0.05, 0.5), (float("nan"), 0.0, 0.0, 1.0)]
    data = b"".join(struct.pack("<ffff", *p) for p in pts)
    f = [("x", FLOAT32, 0), ("y", FLOAT32, 4), ("z", FLOAT32, 8), ("confidence", FLOAT32, 12)]
    write("cloud_conversion", "decoder_points", cloud(f, 3, 1, 16, 48, data))

    rays = []
    for i in range(8):
        rays.append(struct.pack("<ffffffB", 0.4 + 0.1 * i, 0.01 * i, 0.0, 0.05, -0.03, 0.01, i % 5) + b"\0\0\0")
    f = [("x", FLOAT32, 0), ("y", FLOAT32, 4), ("z", FLOAT32, 8), ("sx", FLOAT32, 12), ("sy", FLOAT32, 16),
         ("sz", FLOAT32, 20), ("state", UINT8, 24)]
    # Rotated a quarter turn about z and shifted: (0, 0, 0.707, 0.707), 0.5 m forward.
    write("cloud_conversion", "ray_ends_organized", cloud(f, 4, 2, 28, 112, b"".join(rays), (0, 0, 45, 45, 8, 0, 0)))

    data = b"".join(struct.pack("<ddd", 0.3 * i, 0.1, 0.2) + struct.pack("<ddd", 0.0, 0.0, 0.0) for i in range(3))
    f = [("x", FLOAT64, 0), ("y", FLOAT64, 8), ("z", FLOAT64, 16), ("sx", FLOAT64, 24), ("sy", FLOAT64, 32),
         ("sz", FLOAT64, 40)]
    write("cloud_conversion", "float64_rays", cloud(f, 3, 1, 48, 144, data))

    # Rows padded beyond width * point_step.
    data = b"".join(struct.pack("<fff", 0.5, 0.1 * i, 0.0) + b"\xAA" * 4 for i in range(4))
    f = [("x", FLOAT32, 0), ("y", FLOAT32, 4), ("z", FLOAT32, 8)]
    write("cloud_conversion", "padded_rows", cloud(f, 1, 4, 12, 16, data))


def main():
    for target in ("oi_parsers", "sim_robot", "rig_parser", "scene_parser", "decoder_image", "decoder_rig",
                   "cloud_conversion"):
        os.makedirs(os.path.join(CORPUS, target), exist_ok=True)
    oi_parsers()
    sim_robot()
    rigs()
    scenes()
    decoder_images()
    clouds()


if __name__ == "__main__":
    main()
