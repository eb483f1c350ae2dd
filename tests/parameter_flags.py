#!/usr/bin/env python3
"""Every parameter the library names in its errors (ParameterError("name", ...) in core/ and runtime/)
has its command-line flag in the one table (probe::parameterFlag, core/src/error.cpp), or is one of
the settings no flag sets. A new name fails here until it is placed in one or the other."""
import pathlib
import re
import sys

root = pathlib.Path(__file__).resolve().parent.parent
# Settings that scenes and the runtime's FilterSettings set, and no command-line flag does.
NO_FLAG = {"computedLevels", "pyramidDepth", "inFlight", "batchSize"}

thrown = set()
for folder in ("core", "runtime"):
    for path in (root / folder).rglob("*.cpp"):
        thrown |= set(re.findall(r'ParameterError\("([^"]+)"', path.read_text()))
table = set(re.findall(r'\{"([^"]+)", "--[a-z-]+"\}', (root / "core/src/error.cpp").read_text()))
unplaced = sorted(thrown - table - NO_FLAG)
stale = sorted((table | NO_FLAG) - thrown)
for name in unplaced:
    print(f"FAIL ParameterError(\"{name}\") has no flag in probe::parameterFlag and is not a setting without one")
for name in stale:
    print(f"FAIL \"{name}\" is listed but the library throws no ParameterError of that name")
if unplaced or stale or not thrown:
    sys.exit(1)
print(f"parameter flags: {len(thrown)} names, {len(thrown & table)} with a flag, {len(thrown & NO_FLAG)} without")
