#!/usr/bin/env python3
"""Reads ThreadSanitizer reports (files written with TSAN_OPTIONS log_path) and fails when one
is ours: a report with a stack (an access, a lock, a mutex) whose first frame below TSan's
interceptors and inlined system headers is a source file of this project. Reports inside
libraries we do not build (gRPC, protobuf, abseil, Mesa, LLVM, the Vulkan layers: not
instrumented, so their synchronization is invisible to TSan) are counted by kind, not failed on.

    tests/sanitize/tsan_ours.py EXECUTABLES REPORT_FILE...
EXECUTABLES: the instrumented executables' names, comma-separated (their interceptor frames
have no sources).
"""
import re
import sys

# "#3 name /path/to/file.cpp:12:3 (module+0x..)" or "#3 name <null> (module+0x..)".
FRAME = re.compile(r"#\d+ .*? (<null>|/\S+?)(?::\d+)*(?::\d+)? \(([^+)]+)")


def ours_at_top(stack, executables):
    """Walks a stack from the top past TSan's interceptors (no source, in the executable) and
    inlined system headers (/usr: the standard library, gRPC's and protobuf's inline layers):
    the first frame left decides. Our source file: ours. A library without sources, or a
    generated message (proto/gen): not ours."""
    for match in FRAME.finditer(stack):
        path, module = match.group(1), match.group(2)
        if path == "<null>":
            if module.endswith(executables):
                continue  # an interceptor (memcpy, operator new, pthread_mutex_lock...)
            return False
        if path.startswith("/usr/"):
            continue
        return "/proto/gen/" not in path
    return False


def ours(report, executables):
    for section in re.split(r"\n  (?=\S)", report):
        if section.startswith(("Thread T", "Location is", "As if")) or "created at:" in section:
            continue
        if ours_at_top(section, executables):
            return True
    return False


def main():
    executables = tuple(sys.argv[1].split(","))
    reports = []
    for path in sys.argv[2:]:
        with open(path, errors="replace") as f:
            reports += f.read().split("WARNING: ThreadSanitizer: ")[1:]
    kinds = {}
    failing = []
    for report in reports:
        kind = report.split(" (pid")[0]
        kinds[kind] = kinds.get(kind, 0) + 1
        if ours(report, executables):
            failing.append(report)
    print(f"ThreadSanitizer: {len(reports)} reports, {len(failing)} in our code"
          + "".join(f"; {n} {k}" for k, n in sorted(kinds.items())))
    for report in failing:
        print("WARNING: ThreadSanitizer: " + report.split("SUMMARY")[0])
    return 1 if failing else 0


if __name__ == "__main__":
    sys.exit(main())
