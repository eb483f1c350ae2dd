# Sourced by the bench scripts: the header every benchmark report starts with, so that a report says
# what ran where, when and how. The command line is the one the script was started with.
#
#   bench_command="bench/scripts/NAME${*:+$(printf " %q" "$@")}"   (set by the script before it parses its arguments)
#   bench_header TITLE DEVICE            prints the Markdown header; DEVICE: "name, driver" or "CPU only"
#   bench_device REPORT_JSON             prints "name, driver" from a probefilter report.json
# BENCH_REVISION names the revision where the bench runs from a copy of the tree and a bundle built
# from it (scripts/bundle-runtime) on another machine.

bench_device() {
    python3 -c "import json, sys; d = json.load(open(sys.argv[1]))['device']; print(d['name'] + ', driver ' + d['driver'])" "$1"
}

bench_header() {
    local title=$1 device=$2 root revision
    root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
    revision=${BENCH_REVISION:-$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo "not a git checkout")}
    if [[ -z ${BENCH_REVISION:-} && -n $(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null) ]]; then
        revision+=" (with local changes)"
    fi
    echo "# $title"
    echo
    echo "- command: \`${bench_command}\`"
    echo "- date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "- device: $device"
    echo "- machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores," \
        "$(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo)"
    echo "- revision: $revision"
    echo
}
