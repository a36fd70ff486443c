#!/usr/bin/env python3
"""How many tests ran, skipped and failed, from CTest's JUnit file.

    scripts/test_summary.py build/ctest-results.xml

Prints one line (and the names of the tests skipped or failed). Exit 1 when a
test failed, or in CI (CI set, not "false" or "0") when one was skipped: there
every requirement must be present."""
import os
import sys
import xml.etree.ElementTree as ET


def main(path):
    cases = ET.parse(path).getroot().iter("testcase")
    passed, skipped, failed = [], [], []
    for case in cases:
        name, status = case.get("name"), case.get("status")
        skip = case.find("skipped")
        not_run = skip is not None and skip.get("message", "").startswith("Fixture dependency failed")
        if status == "fail" or case.find("failure") is not None or not_run:  # CTest counts not run as failed
            failed.append(name)
        elif status == "run":
            passed.append(name)
        else:  # notrun (skipped, or a fixture failed) and disabled
            skipped.append(name)
    ran = len(passed) + len(failed)
    print(f"tests: {ran} ran, {len(skipped)} skipped, {len(failed)} failed ({len(passed)} passed)")
    for label, names in (("skipped", skipped), ("failed", failed)):
        for n in names:
            print(f"  {label}: {n}")
    ci = os.environ.get("CI", "") not in ("", "false", "0")
    return 1 if failed or (ci and skipped) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
