#!/usr/bin/env bash
# scripts/checker-pass refuses a name that is not a uniform glTF table at 128^2 with one line and exit
# 2 before it fits or writes anything: the tables named before it are left as they were.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
before=$(cat "$root"/tables/*.json "$root"/tables/*.h | sha256sum)
# No probefit: the names are checked first.
err=$(PROBEFIT=/nonexistent timeout 10 "$root/scripts/checker-pass" gltf128_const4 gltf256_quad8 2>&1 >/dev/null)
code=$?
[[ $code -eq 2 ]] || { echo "checker_pass_refuses: exit $code, expected 2: $err" >&2; exit 1; }
[[ $err == "checker-pass: gltf256_quad8 is not a uniform glTF table at 128^2" ]] ||
    { echo "checker_pass_refuses: unexpected message: $err" >&2; exit 1; }
[[ $(cat "$root"/tables/*.json "$root"/tables/*.h | sha256sum) == "$before" ]] ||
    { echo "checker_pass_refuses: tables changed" >&2; exit 1; }
echo "checker_pass_refuses: $err (exit 2, tables unchanged)"
