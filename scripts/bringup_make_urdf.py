#!/usr/bin/python3
"""Prints the robot description (URDF) of the structured-light Create for a rig (calibration) file.

    bringup_make_urdf.py RIG_FILE [--template urdf/create.urdf.in] [--body urdf/create.yaml]

Fills the placeholders of the URDF template from the rig file, the one place the camera mount and
the projector pose live (Debian has no xacro, so this replaces it):
  mount.parent_frame, mount.xyz, mount.rpy        pose of camera_link in platform_edge (m, rad)
  projector_pose.rotation (row-major 3x3), .translation
                                                  projector_optical_frame in camera_optical_frame:
                                                  p_camera = rotation * p_projector + translation
and the body's radius from urdf/create.yaml (robot_radius, m), the one place it is written.
The launch files run it as
  <param name="robot_description" command="/usr/bin/python3 $(dirname)/../scripts/bringup_make_urdf.py $(arg calibration_file)"/>
An invalid rig or body file stops it with exit status 1 and a message naming the file and the key;
so does a key of the rig file that the rig reader (sl_rig) does not know.
"""

import argparse
import math
import os
import re
import sys

import yaml

HERE = os.path.dirname(os.path.realpath(__file__))
DEFAULT_TEMPLATE = os.path.join(HERE, "..", "urdf", "create.urdf.in")
DEFAULT_BODY = os.path.join(HERE, "..", "urdf", "create.yaml")

BODY_TOP = 0.074      # m, top of the Create's body above the floor (the template's base visual)
MAST_ABOVE = 0.03     # m, the mast plate reaches this far above the camera's optical centre
MAST_BEHIND = 0.045   # m, the mast plate stands this far behind the camera's optical centre
LINKS = ("base_link", "platform_edge")  # frames of the template the mount may be given in


class RigError(Exception):
    """A missing or invalid key of the rig file."""


# The keys the rig reader (sl_rig/src/rig_io.cpp, parseRoot) allows in each mapping, by its path: a
# key outside them is refused, so that a misspelt optional key does not leave a default in place.
RIG_KEYS = {
    "": ("format_version", "camera", "projector", "projector_pose", "pattern", "mount", "depth_tables"),
    "camera": ("width", "height", "K", "D", "focus_distance", "f_number", "pixel_pitch"),
    "projector": ("width", "height", "K", "D", "focus_distance", "f_number", "pixel_pitch"),
    "projector_pose": ("rotation", "translation"),
    "pattern": ("rows", "cols", "primitive_width", "primitive_height", "gap_x", "gap_y", "offset_x", "offset_y",
                "flip_x", "flip_y"),
    "mount": ("parent_frame", "xyz", "rpy"),
    "depth_tables": ("distances", "linear", "rational"),
    "depth_tables.linear": ("a", "b", "rms"),
    "depth_tables.rational": ("a", "b", "c", "rms"),
}


def edit_distance(a, b):
    """Optimal string alignment distance: Levenshtein plus the swap of two neighbours."""
    d = [[i + j if i * j == 0 else 0 for j in range(len(b) + 1)] for i in range(len(a) + 1)]
    for i in range(1, len(a) + 1):
        for j in range(1, len(b) + 1):
            d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1]))
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                d[i][j] = min(d[i][j], d[i - 2][j - 2] + 1)
    return d[len(a)][len(b)]


def nearest_key(key, allowed):
    """The one allowed key within a typo or two of `key` (as sl_rig::nearestKey), or None."""
    limit = max(1, len(key) // 3)
    distances = sorted((edit_distance(key, a), a) for a in allowed)
    best = [a for d, a in distances if d == distances[0][0]]
    return best[0] if distances[0][0] <= limit and len(best) == 1 else None


def check_keys(rig):
    """Refuses a key that the rig reader does not know, at every level, naming it."""
    for path in sorted(RIG_KEYS):
        node = rig
        for part in path.split(".") if path else ():
            node = node.get(part) if isinstance(node, dict) else None
        if node is None:
            continue  # absent: a required one is reported where it is read
        if not isinstance(node, dict):
            raise RigError("%s: must be a mapping" % (path or "<top level>"))
        prefix = path + "." if path else ""
        for key in node:
            if not isinstance(key, str):
                raise RigError("%s%r: a key must be a name" % (prefix, key))
            if key in RIG_KEYS[path]:
                continue
            hint = nearest_key(key, RIG_KEYS[path])
            raise RigError("%s%s: unknown key%s (allowed: %s)" % (prefix, key, ", did you mean '%s'?" % hint
                                                                   if hint else "", ", ".join(sorted(RIG_KEYS[path]))))


def numbers(node, key, count):
    """The list at node[key] as `count` finite floats."""
    parts = key.split(".")
    value = node
    for part in parts:
        if not isinstance(value, dict) or part not in value:
            raise RigError("%s: missing" % key)
        value = value[part]
    if not isinstance(value, (list, tuple)) or len(value) != count:
        raise RigError("%s: expected a list of %d numbers" % (key, count))
    out = []
    for v in value:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise RigError("%s: %r is not a finite number" % (key, v))
        out.append(float(v))
    return out


def rpy_from_matrix(r):
    """URDF roll, pitch, yaw (R = Rz(yaw) Ry(pitch) Rx(roll)) of a row-major 3x3 rotation."""
    r00, r01, _, r10, r11, _, r20, r21, r22 = r
    pitch = math.atan2(-r20, math.hypot(r00, r10))
    if math.hypot(r00, r10) < 1e-9:  # gimbal lock: put all of the remaining turn into yaw
        return 0.0, pitch, math.atan2(-r01, r11)
    return math.atan2(r21, r22), pitch, math.atan2(r10, r00)


def check_rotation(r, key):
    """Orthonormal with determinant +1 (the rig loader's check, repeated for a clear message)."""
    m = [r[0:3], r[3:6], r[6:9]]
    for i in range(3):
        for j in range(3):
            dot = sum(m[i][k] * m[j][k] for k in range(3))
            if abs(dot - (1.0 if i == j else 0.0)) > 1e-3:
                raise RigError("%s: is not orthonormal" % key)
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    if det < 0.0:
        raise RigError("%s: has determinant -1 (a reflection)" % key)


def fmt(values):
    return " ".join("%.9g" % v for v in values)


def robot_radius(body):
    """robot_radius (m) of the parsed body file, checked."""
    if not isinstance(body, dict) or "robot_radius" not in body:
        raise RigError("robot_radius: missing (m, the robot's disc)")
    r = body["robot_radius"]
    if isinstance(r, bool) or not isinstance(r, (int, float)) or not (0.0 < r < 2.0):
        raise RigError("robot_radius: %r is not a number in (0, 2) m" % (r,))
    return float(r)


def placeholders(rig, rig_file, radius):
    """Every value the template needs, from the parsed rig file and the body's radius (m)."""
    if not isinstance(rig, dict):
        raise RigError("not a YAML mapping")
    check_keys(rig)
    mount = rig.get("mount")
    if not isinstance(mount, dict):
        raise RigError("mount: missing (pose of camera_link in platform_edge)")
    parent = mount.get("parent_frame", "platform_edge")
    if parent not in LINKS:
        raise RigError("mount.parent_frame: '%s' is not a frame of the robot model (one of %s)" %
                       (parent, ", ".join(LINKS)))
    xyz = numbers(rig, "mount.xyz", 3)
    rpy = numbers(rig, "mount.rpy", 3)
    rotation = numbers(rig, "projector_pose.rotation", 9)
    check_rotation(rotation, "projector_pose.rotation")
    translation = numbers(rig, "projector_pose.translation", 3)
    if max(abs(v) for v in translation) > 10.0:
        raise RigError("projector_pose.translation: a baseline over 10 m is not metres (mm given?)")

    # The mast is drawn in platform_edge: from the mount's position expressed there.
    edge_x, edge_z = xyz[0], xyz[2]
    if parent == "base_link":
        edge_x -= radius
    mast_height = max(0.02, edge_z + MAST_ABOVE - BODY_TOP)
    return {
        "rig_file": os.path.abspath(rig_file).replace("--", "- -"),  # no "--" inside an XML comment
        "robot_radius": "%.9g" % radius,
        "mount_parent": parent,
        "mount_xyz": fmt(xyz),
        "mount_rpy": fmt(rpy),
        "projector_xyz": fmt(translation),
        "projector_rpy": fmt(rpy_from_matrix(rotation)),
        "mast_x": "%.9g" % (edge_x - MAST_BEHIND),
        "mast_base_z": "%.9g" % BODY_TOP,
        "mast_height": "%.9g" % mast_height,
        "mast_half_height": "%.9g" % (mast_height / 2.0),
    }


def fill(template, values, template_file):
    def one(match):
        name = match.group(1)
        if name not in values:
            raise RigError("%s: unknown placeholder ${%s}" % (template_file, name))
        return values[name]
    return re.sub(r"\$\{([a-z_]+)\}", one, template)


def main(argv):
    parser = argparse.ArgumentParser(description="Robot description (URDF) of the structured-light Create "
                                     "from a rig (calibration) file; printed on stdout.")
    parser.add_argument("rig_file", help="rig file, e.g. sl_projector/config/default_rig.yaml")
    parser.add_argument("--template", default=DEFAULT_TEMPLATE, help="URDF template (default: %(default)s)")
    parser.add_argument("--body", default=DEFAULT_BODY, help="body file with robot_radius (default: %(default)s)")
    args = parser.parse_args(argv)
    try:
        with open(args.rig_file) as f:
            rig = yaml.safe_load(f)
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as e:
        sys.stderr.write("bringup_make_urdf: %s: %s\n" % (args.rig_file, e))
        return 1
    try:
        with open(args.template) as f:
            template = f.read()
    except OSError as e:
        sys.stderr.write("bringup_make_urdf: template %s: %s\n" % (args.template, e))
        return 1
    try:
        with open(args.body) as f:
            radius = robot_radius(yaml.safe_load(f))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as e:
        sys.stderr.write("bringup_make_urdf: %s: %s\n" % (args.body, e))
        return 1
    except RigError as e:
        sys.stderr.write("bringup_make_urdf: %s: %s\n" % (args.body, e))
        return 1
    try:
        urdf = fill(template, placeholders(rig, args.rig_file, radius), args.template)
    except RigError as e:
        sys.stderr.write("bringup_make_urdf: %s: %s\n" % (args.rig_file, e))
        return 1
    sys.stdout.write(urdf)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
