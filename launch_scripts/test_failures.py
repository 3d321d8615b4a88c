#!/usr/bin/python3
"""Prints the failure messages of every failed test case in the JUnit result files under a folder.

The test command shows only a one-line verdict per failed test; this gives the assertion text
(expected and actual values) so a failure can be read from the test command's output alone.
"""
import pathlib
import sys
import xml.etree.ElementTree as ET

MAX_CHARS = 3000


def main(folder):
    for path in sorted(pathlib.Path(folder).rglob("*.xml")):
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as error:
            print(f"{path.name}: unreadable result file ({error})")
            continue
        for case in root.iter("testcase"):
            for kind in ("failure", "error"):
                for problem in case.findall(kind):
                    text = (problem.get("message") or "") + "\n" + (problem.text or "")
                    text = text.strip()
                    if len(text) > MAX_CHARS:
                        text = text[:MAX_CHARS] + " [...]"
                    print(f"--- {path.name}: {case.get('classname')}.{case.get('name')} ({kind})")
                    print(text)


if __name__ == "__main__":
    main(sys.argv[1])
