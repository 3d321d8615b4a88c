#!/usr/bin/python3
"""Prints the failure messages of every failed test case in the JUnit result files under a folder.

The test command shows only a one-line verdict per failed test; this gives the assertion text
(expected and actual values) so a failure can be read from the test command's output alone.
For a failed rostest it also prints what the test printed and the last lines every node of that
launch logged (the run's folder under the ROS log directory), so a failure on another machine can
be diagnosed without its files.
"""
import os
import pathlib
import re
import sys
import xml.etree.ElementTree as ET

MAX_CHARS = 3000
NODE_LOG_LINES = 25


def ros_log_dir():
    if os.environ.get("ROS_LOG_DIR"):
        return pathlib.Path(os.environ["ROS_LOG_DIR"])
    home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    return pathlib.Path(home) / "log"


def run_ids(folder, test_name):
    """The run ids of the rostest launches whose test node is `test_name`."""
    ids = []
    for path in sorted(pathlib.Path(folder).rglob("rostest-*.xml")):
        text = path.read_text(errors="replace")
        if f'name="test{test_name}"' in text:
            ids += re.findall(r"run_id\[([0-9a-f-]+)\]", text)[:1]
    return ids


def tail(path, lines):
    content = path.read_text(errors="replace").splitlines()
    # Colour codes make the log hard to read in a CI page.
    return [re.sub(r"\x1b\[[0-9;]*m", "", line) for line in content[-lines:]]


def print_node_logs(folder, test_name):
    for run_id in run_ids(folder, test_name):
        run_dir = ros_log_dir() / run_id
        if not run_dir.is_dir():
            print(f"    (no node logs: {run_dir} is missing)")
            continue
        for log in sorted(run_dir.glob("*-std*.log")):
            if log.stat().st_size == 0:
                continue
            own = log.name.startswith(test_name + "-")
            shown = tail(log, 200 if own else NODE_LOG_LINES)
            print(f"    --- {run_dir.name}/{log.name} (last {len(shown)} lines)")
            for line in shown:
                print("    " + line[:400])


def main(folder):
    for path in sorted(pathlib.Path(folder).rglob("*.xml")):
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as error:
            print(f"{path.name}: unreadable result file ({error})")
            continue
        failed = False
        for case in root.iter("testcase"):
            for kind in ("failure", "error"):
                for problem in case.findall(kind):
                    text = (problem.get("message") or "") + "\n" + (problem.text or "")
                    text = text.strip()
                    if len(text) > MAX_CHARS:
                        text = text[:MAX_CHARS] + " [...]"
                    print(f"--- {path.name}: {case.get('classname')}.{case.get('name')} ({kind})")
                    print(text)
                    failed = True
        match = re.fullmatch(r"rosunit-(.+)\.xml", path.name)
        if failed and match:
            print_node_logs(folder, match.group(1))


if __name__ == "__main__":
    main(sys.argv[1])
