#!/usr/bin/env python3
"""Runs one FreeCAD test script (headless with freecadcmd, or the GUI under xvfb-run) in a fresh,
isolated FREECAD_USER_HOME whose Mod folder is the build-tree workbench, and fails on a non-zero
exit code, a missing success marker, or any "Traceback" in the log (FreeCAD swallows exceptions
raised in callbacks and prints them) other than a Job's deliberate JobFailed (JOB_FAILED).
Progress lines like "( 42 %)" are filtered from the log."""

import argparse
import os
import re
import shutil
import subprocess
import sys

MARKER = "CURVEDSLICER-TESTS-OK"

# A Job whose recompute fails raises JobFailed out of its execute(): that is how a Python feature
# enters FreeCAD's error state, and FreeCAD prints the raise as a traceback. Exactly these
# blocks (every frame the raise in JobProxy.execute, the exception JobFailed) are expected
# output, not a swallowed exception; any other traceback still fails the test.
JOB_FAILED = re.compile(
    r"Traceback \(most recent call last\):\n"
    r"(?:  File \"[^\"\n]*/freecad/curvedslicer/objects/job\.py\", line \d+, in execute\n"
    r"    raise JobFailed\([^\n]*\n(?:\s*\^+\n)?)+"
    r"<class 'freecad\.curvedslicer\.objects\.job\.JobFailed'>: [^\n]*\n")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--mode", choices=["headless", "gui"], required=True)
    parser.add_argument("--freecad", required=True, help="freecadcmd (headless) or freecad (gui)")
    parser.add_argument("--xvfb-run", default="xvfb-run")
    parser.add_argument("--home", required=True, help="FREECAD_USER_HOME for this test")
    parser.add_argument("--mod", required=True, help="the Mod folder holding CurvedSlicer")
    parser.add_argument("--script", required=True)
    parser.add_argument("--timeout", type=float, default=880.0)
    args = parser.parse_args()

    shutil.rmtree(args.home, ignore_errors=True)
    os.makedirs(os.path.join(args.home, "tmp"))
    os.symlink(os.path.abspath(args.mod), os.path.join(args.home, "Mod"))
    env = dict(os.environ)
    env.update({
        "FREECAD_USER_HOME": args.home,
        "CURVEDSLICER_TEST_TMP": os.path.join(args.home, "tmp"),
        "CURVEDSLICER_TEST_DIR": os.path.dirname(os.path.abspath(args.script)),
        "CURVEDSLICER_SOURCE_DIR": os.path.abspath(
            os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")),
        "CURVEDSLICER_FREECADCMD": shutil.which("freecadcmd") or "freecadcmd",
        "QTWEBENGINE_DISABLE_SANDBOX": "1",
        "PYTHONDONTWRITEBYTECODE": "1",
    })
    if args.mode == "headless":
        command = [args.freecad, args.script]
    else:
        command = [args.xvfb_run, "-a", "-s", "-screen 0 1280x1024x24", args.freecad, args.script]
    try:
        run = subprocess.run(command, env=env, cwd=args.home, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, timeout=args.timeout)
        log, code = run.stdout.decode("utf-8", "replace"), run.returncode
    except subprocess.TimeoutExpired as expired:
        log = (expired.stdout or b"").decode("utf-8", "replace")
        code = "timeout after %g s" % args.timeout
    log = re.sub(r"\(\s*\d+\s*%\)", "", log.replace("\r", "\n"))
    log = "\n".join(line for line in log.splitlines() if line.strip())
    print(log)
    problems = []
    if code != 0:
        problems.append("exit code %s" % code)
    if "Traceback" in JOB_FAILED.sub("", log + "\n"):
        problems.append("a Traceback in the log")
    if MARKER not in log:
        problems.append("no %s marker (the script did not finish)" % MARKER)
    if problems:
        print("FAILED: " + "; ".join(problems))
        return 1
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
