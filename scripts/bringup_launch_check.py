#!/usr/bin/python3
"""roslaunch's own file check (roslaunch-check) for a package whose launch/ and test/ folders are
symbolic links, as sl_bringup's are (they point to the top of the repository).

    bringup_launch_check.py PACKAGE_DIR [roslaunch-check arguments: -o RESULT.xml [-i] [-t] FILE]

rospkg.get_package_name() resolves symbolic links before it looks for package.xml, so for
catkin_ws/src/sl_bringup/launch/sim.launch it searches /repo/launch, /repo, ... and finds no package;
roslaunch-check then fails before checking anything. This wrapper teaches get_package_name that
files below the real location of PACKAGE_DIR's linked folders belong to that package, and then runs
/usr/share/roslaunch/scripts/roslaunch-check unchanged (arguments, includes, substitutions, node
types, the package's declared dependencies; JUnit result file).
"""

import os
import runpy
import sys

import rospkg
import rospkg.rospack

CHECK = "/usr/share/roslaunch/scripts/roslaunch-check"


def main():
    if len(sys.argv) < 3:
        sys.stderr.write(__doc__)
        return 2
    package_dir = os.path.abspath(sys.argv[1])
    package = rospkg.get_package_name(os.path.join(package_dir, "package.xml"))
    if not package:
        sys.stderr.write("bringup_launch_check: no package.xml in %s\n" % package_dir)
        return 2
    linked = [os.path.realpath(os.path.join(package_dir, entry)) for entry in os.listdir(package_dir)
              if os.path.islink(os.path.join(package_dir, entry)) and os.path.isdir(os.path.join(package_dir, entry))]
    original = rospkg.get_package_name

    def get_package_name(path):
        name = original(path)
        if name:
            return name
        real = os.path.realpath(path)
        for folder in linked:
            if real == folder or real.startswith(folder + os.sep):
                return package
        return None

    rospkg.get_package_name = get_package_name
    rospkg.rospack.get_package_name = get_package_name
    sys.argv = [CHECK] + sys.argv[2:]
    runpy.run_path(CHECK, run_name="__main__")
    return 0


if __name__ == "__main__":
    sys.exit(main())
