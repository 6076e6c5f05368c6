#!/usr/bin/python3
"""Counts test cases in the JUnit XML files catkin writes (gtest, rostest, rosunit).

catkin_test_results counts differently per file type (it adds up suite totals and failure
elements), so the closing line is counted here from the <testcase> elements themselves.
Prints the names of failed cases with the first lines of their failure messages, the number of
skipped ones (if any), and last the line
"N passed, N failed" that CI reads.
"""
import os
import sys
import xml.etree.ElementTree as ET

root_dir = sys.argv[1]
# --missing N: result files that should exist and do not (counted as failures by the caller's check).
missing = int(sys.argv[sys.argv.index("--missing") + 1]) if "--missing" in sys.argv else 0
passed = skipped = 0
failed = missing
failures = []
for dirpath, _, files in os.walk(root_dir):
    for name in sorted(files):
        if not name.endswith(".xml"):
            continue
        path = os.path.join(dirpath, name)
        try:
            tree = ET.parse(path)
        except ET.ParseError as e:
            failed += 1
            failures.append("%s: unreadable result file (%s)" % (path, e))
            continue
        cases = list(tree.getroot().iter("testcase"))
        if not cases:
            # A rostest whose test node never ran leaves a file without test cases.
            failed += 1
            failures.append("%s: no test case ran" % os.path.relpath(path, root_dir))
            continue
        for case in cases:
            label = "%s.%s" % (case.get("classname", "?"), case.get("name", "?"))
            problems = case.findall("failure") + case.findall("error")
            if problems:
                failed += 1
                # The assertion texts, so that a CI log alone tells what failed: up to 12 lines of
                # each, and 45 of a closed-loop test's decision trail.
                detail = []
                for problem in problems:
                    lines = (problem.get("message") or problem.text or "").strip().splitlines()
                    detail += lines[:45 if "changes of decision" in "".join(lines[:2]) else 12]
                failures.append("%s: %s%s" % (os.path.relpath(path, root_dir), label,
                                              "".join("\n    " + line for line in detail)))
            elif case.find("skipped") is not None or case.get("status") == "notrun":
                skipped += 1
            else:
                passed += 1
for f in failures:
    print("FAILED " + f)
if skipped:
    print("%d skipped" % skipped)
print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed or passed == 0 else 0)
