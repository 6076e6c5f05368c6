#!/usr/bin/env python3
"""Coverage of a cover.test run against the scene's ground truth.

    scripts/cover_truth.py test/scenes/cover_lounge.yaml $ROS_HOME/cover_cover_lounge_1_path.txt [--minutes=10,20,30]

Reads a scene of test/scenes (walls: vertical planes; obstacles: boxes and upright cylinders that
reach below the robot's working height, 0.173 m) and the true path that cover_rostest writes
(~path_file: "t x y yaw" per line, world frame). Measures as the kinematic CoverageLoop test does,
at 0.05 m cells: the reachable floor is every free cell within the robot's radius of a centre cell
(a free cell whose centre is at least 0.2425 m from every occupied cell's centre, 8-connected to the
start); a cell is covered when the disc passed over its centre. Prints the covered share of the
reachable floor at 1, 2, 5 and 10 minutes (or the --minutes given) and the median uncovered band
along the straight walls (probes every 0.05 m, 0.3 m from the corners, up to 0.6 m inward; probes
that meet furniture first are left out).
"""
import math
import sys

import yaml

RES = 0.05  # m, cell side (map_resolution)
WORKING_HEIGHT = 0.173  # m: objects reaching below this are obstacles
ROBOT_RADIUS = 0.1675  # m (urdf/create.yaml)
CENTRE_CLEARANCE = 0.2425  # m, CoveragePlanner's centreClearance()
MINUTES = (60.0, 120.0, 300.0, 600.0)


def fail(text):
    sys.exit('cover_truth.py: ' + text)


class Scene:
    """The scene's floor plan: the walls' box and the footprints of the low obstacles."""

    def __init__(self, path):
        try:
            with open(path) as f:
                doc = yaml.safe_load(f)
            objects = doc['objects']
        except (OSError, yaml.YAMLError, KeyError, TypeError) as e:
            fail('%s: not a scene file with objects (%s)' % (path, e))
        self.name = doc.get('name', path)
        xs, ys, self.shapes = [], [], []
        for o in objects:
            try:
                self._add(o, xs, ys)
            except (KeyError, TypeError, ValueError, IndexError) as e:
                fail('%s: object %s: %s' % (path, o.get('name', '?') if isinstance(o, dict) else o, e))
        if len(xs) < 2 or len(ys) < 2:
            fail('%s: needs two walls across x and two across y' % path)
        self.x0, self.x1, self.y0, self.y1 = min(xs), max(xs), min(ys), max(ys)

    def _add(self, o, xs, ys):
        p = [float(v) for v in o['position']]
        kind = o['type']
        if kind == 'plane':
            n = o['normal']
            if not o.get('floor') and abs(n[2]) < 0.5:
                (xs if abs(n[0]) > abs(n[1]) else ys).append(p[0] if abs(n[0]) > abs(n[1]) else p[1])
        elif kind == 'box':
            sx, sy, sz = (float(v) for v in o['size'])
            if p[2] - 0.5 * sz < WORKING_HEIGHT:
                self.shapes.append(('box', p[0], p[1], 0.5 * sx, 0.5 * sy, float(o.get('rpy', [0, 0, 0])[2])))
        elif kind == 'cylinder':
            rpy = o.get('rpy', [0, 0, 0])
            upright = abs(rpy[0]) < 0.1 and abs(rpy[1]) < 0.1
            if upright and p[2] - 0.5 * float(o['height']) < WORKING_HEIGHT:
                self.shapes.append(('cylinder', p[0], p[1], float(o['radius'])))

    def occupied(self, x, y):
        if not (self.x0 < x < self.x1 and self.y0 < y < self.y1):
            return True
        for s in self.shapes:
            if s[0] == 'cylinder':
                if math.hypot(x - s[1], y - s[2]) <= s[3]:
                    return True
            else:
                c, n = math.cos(s[5]), math.sin(s[5])
                dx, dy = x - s[1], y - s[2]
                if abs(c * dx + n * dy) <= s[3] and abs(-n * dx + c * dy) <= s[4]:
                    return True
        return False


class Truth:
    """The scene at 0.05 m cells: occupied cells (any of 5 x 5 samples inside), reachable floor."""

    def __init__(self, scene, start):
        self.scene = scene
        self.ox, self.oy = scene.x0 - 0.2, scene.y0 - 0.2
        self.nx = int((scene.x1 - scene.x0 + 0.4) / RES) + 1
        self.ny = int((scene.y1 - scene.y0 + 0.4) / RES) + 1
        self.occ = {(i, j) for i in range(self.nx) for j in range(self.ny) if self._any_sample(i, j)}
        self.floor = self._reachable_floor(self.cell(*start))

    def cell(self, x, y):
        return int(math.floor((x - self.ox) / RES)), int(math.floor((y - self.oy) / RES))

    def centre(self, i, j):
        return self.ox + (i + 0.5) * RES, self.oy + (j + 0.5) * RES

    def _any_sample(self, i, j):
        return any(self.scene.occupied(self.ox + (i + (a + 0.5) / 5) * RES, self.oy + (j + (b + 0.5) / 5) * RES)
                   for a in range(5) for b in range(5))

    def _disc(self, radius):
        k = int(radius / RES) + 1
        return [(a, b) for a in range(-k, k + 1) for b in range(-k, k + 1) if math.hypot(a, b) * RES <= radius]

    def _reachable_floor(self, start):
        near = self._disc(CENTRE_CLEARANCE)
        blocked = {(i + a, j + b) for (i, j) in self.occ for (a, b) in near
                   if math.hypot(a, b) * RES < CENTRE_CLEARANCE}
        if start in blocked:
            fail('the start %s is not a centre cell (too near an obstacle)' % (start,))
        seen, stack = {start}, [start]
        while stack:
            i, j = stack.pop()
            for a in (-1, 0, 1):
                for b in (-1, 0, 1):
                    q = (i + a, j + b)
                    if q not in seen and q not in blocked and 0 <= q[0] < self.nx and 0 <= q[1] < self.ny:
                        seen.add(q)
                        stack.append(q)
        disc = self._disc(ROBOT_RADIUS + 1e-9)
        return {(i + a, j + b) for (i, j) in seen for (a, b) in disc} - self.occ


def read_path(path):
    poses = []
    try:
        with open(path) as f:
            for number, line in enumerate(f, 1):
                fields = line.split()
                if len(fields) != 4:
                    continue  # the last line of a run that was stopped may be cut
                try:
                    poses.append(tuple(float(v) for v in fields))
                except ValueError:
                    fail('%s:%d: not "t x y yaw"' % (path, number))
    except OSError as e:
        fail('%s: %s' % (path, e))
    if not poses:
        fail('%s: no poses' % path)
    return poses


def main():
    minutes = MINUTES
    if len(sys.argv) == 4:  # --minutes=10,15,20,30
        if not sys.argv[3].startswith('--minutes='):
            fail('usage: cover_truth.py SCENE.yaml PATH.txt [--minutes=M1,M2,...]')
        try:
            minutes = tuple(60.0 * float(m) for m in sys.argv[3][len('--minutes='):].split(','))
        except ValueError:
            fail('--minutes: a comma-separated list of minutes, got %r' % sys.argv[3])
        if not minutes or any(not math.isfinite(m) or m <= 0.0 for m in minutes) or list(minutes) != sorted(minutes):
            fail('--minutes: positive minutes in increasing order, got %r' % sys.argv[3])
    elif len(sys.argv) != 3:
        fail('usage: cover_truth.py SCENE.yaml PATH.txt [--minutes=M1,M2,...]')
    scene = Scene(sys.argv[1])
    poses = read_path(sys.argv[2])
    truth = Truth(scene, poses[0][1:3])
    disc = [(a, b) for a in range(-5, 6) for b in range(-5, 6)]
    covered, shares, previous = set(), [], None

    def mark(x, y):
        ci, cj = truth.cell(x, y)
        for a, b in disc:
            cx, cy = truth.centre(ci + a, cj + b)
            if math.hypot(cx - x, cy - y) <= ROBOT_RADIUS:
                covered.add((ci + a, cj + b))

    for t, x, y, _ in poses:
        while len(shares) < len(minutes) and t > minutes[len(shares)]:
            shares.append(len(covered & truth.floor) / len(truth.floor))
        steps = 1 if previous is None else int(math.hypot(x - previous[0], y - previous[1]) / (0.5 * RES)) + 1
        for s in range(1, steps + 1):  # every half cell: no gaps at speed
            f = s / steps
            mark(x if previous is None else previous[0] + (x - previous[0]) * f,
                 y if previous is None else previous[1] + (y - previous[1]) * f)
        previous = (x, y)
    while len(shares) < len(minutes):
        shares.append(len(covered & truth.floor) / len(truth.floor))

    def band(x, y, nx, ny):
        for k in range(61):
            d = 0.01 * k
            px, py = x + nx * (d + 0.005), y + ny * (d + 0.005)
            if scene.occupied(px, py):
                return None  # furniture against the wall
            if truth.cell(px, py) in covered:
                return d
        return 0.6

    bands = []
    for k in range(int(round((scene.x1 - scene.x0 - 0.6) / 0.05)) + 1):
        x = scene.x0 + 0.3 + 0.05 * k
        bands += [band(x, scene.y0 + 0.001, 0, 1), band(x, scene.y1 - 0.001, 0, -1)]
    for k in range(int(round((scene.y1 - scene.y0 - 0.6) / 0.05)) + 1):
        y = scene.y0 + 0.3 + 0.05 * k
        bands += [band(scene.x0 + 0.001, y, 1, 0), band(scene.x1 - 0.001, y, -1, 0)]
    bands = sorted(b for b in bands if b is not None)
    print('%s: room %.2f m2, reachable floor %.2f m2; covered at %s min: %s %% (path of %.0f s); '
          'median uncovered band along the walls %.2f m (%d probes)' % (
              scene.name, (scene.x1 - scene.x0) * (scene.y1 - scene.y0), len(truth.floor) * RES * RES,
              '/'.join('%g' % (m / 60) for m in minutes), ' / '.join('%.1f' % (100 * v) for v in shares),
              poses[-1][0], bands[len(bands) // 2] if bands else float('nan'), len(bands)))


if __name__ == '__main__':
    main()
