#!/usr/bin/env python3
"""The install rule as a user runs it: `cmake --install BUILD --component workbench` with a fresh
HOME (no FREECAD_USER_HOME), then a new freecadcmd with that HOME imports freecad.curvedslicer and
its compiled module from the folder the rule chose. On FreeCAD 1.1 this is the versioned
~/.local/share/FreeCAD/v1-1/Mod, on 0.20 and 1.0 ~/.local/share/FreeCAD/Mod."""

import argparse
import os
import shutil
import subprocess
import sys

MARKER = "CURVEDSLICER-TESTS-OK"
PROBE = (
    "import FreeCAD, sys\n"
    "import freecad.curvedslicer as package\n"
    "from freecad.curvedslicer.core import native\n"
    "print('USER-DATA=' + FreeCAD.getUserAppDataDir())\n"
    "print('PACKAGE=' + package.__file__)\n"
    "print('NATIVE=' + native.__file__)\n"
    "sys.stdout.flush()\n"
)


def run(command, env):
    done = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          timeout=300)
    out = done.stdout.decode("utf-8", "replace")
    print("$ " + " ".join(command) + "\n" + out)
    if done.returncode != 0:
        raise SystemExit("FAILED: exit code %d of %s" % (done.returncode, command[0]))
    return out


def value(out, prefix):
    for line in out.splitlines():
        if line.startswith(prefix):
            return line[len(prefix):].strip()
    raise SystemExit("FAILED: no line starting %r in the output" % prefix)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cmake", required=True)
    parser.add_argument("--build", required=True)
    parser.add_argument("--freecadcmd", required=True)
    parser.add_argument("--home", required=True, help="a scratch HOME, emptied first")
    args = parser.parse_args()

    shutil.rmtree(args.home, ignore_errors=True)
    os.makedirs(args.home)
    env = {k: v for k, v in os.environ.items() if not k.startswith("FREECAD_")}
    env["HOME"] = os.path.abspath(args.home)
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    out = run([args.cmake, "--install", args.build, "--component", "workbench"], env)
    mod = value(out, "-- Installing the CurvedSlicer workbench into ")
    probe = os.path.join(args.home, "probe.py")
    with open(probe, "w") as f:
        f.write(PROBE)
    out = run([args.freecadcmd, probe], env)
    user_data = os.path.realpath(value(out, "USER-DATA="))
    installed = os.path.realpath(mod)
    problems = []
    if not installed.startswith(os.path.realpath(args.home) + os.sep):
        problems.append("installed outside HOME: %s" % installed)
    if os.path.dirname(installed) != os.path.join(user_data, "Mod"):
        problems.append("installed into %s, FreeCAD reads %s" % (installed,
                                                                 os.path.join(user_data, "Mod")))
    for key in ("PACKAGE", "NATIVE"):
        loaded = os.path.realpath(value(out, key + "="))
        if not loaded.startswith(installed + os.sep):
            problems.append("%s loaded from %s, not from the install %s" % (key, loaded, installed))
    if problems:
        print("FAILED: " + "; ".join(problems))
        return 1
    print("installed into %s and loaded from there" % installed)
    print(MARKER)
    return 0


if __name__ == "__main__":
    sys.exit(main())
