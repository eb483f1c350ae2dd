#!/usr/bin/env bash
# BC6H KTX2 from probefilter, checked by what the project did not write: ktx-parse (npm) reads the
# container and its descriptor, bcdec (PyPI imagecodecs) decodes the blocks, the Vulkan device's
# texture unit samples them (tests/bc6h_sample) to bcdec's values exactly, and ISPC texcomp's BC6H
# (PyPI ispc-texcomp, profile basic) encodes the same RGBA16F levels beside it (bench/scripts/bc6h.py):
# on four synthetic probes at 32^2, no level of 4x4 or more may fall more than 1 dB of multi-exposure
# PSNR below ISPC's, and every texel decodes finite. The Python packages go into a virtual
# environment in the build folder, the npm package beside the other KTX2 test's.
set -euo pipefail
: "${PROBEFILTER:?}" "${BC6H_SAMPLE:?}" "${BC6H_VENV:?}" "${KTX_PARSE_PREFIX:?}"
root="$(cd "$(dirname "$0")/.." && pwd)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! "$BC6H_VENV/bin/python" -c "import imagecodecs, ispc_texcomp, numpy" 2>/dev/null; then
    python3 -m venv "$BC6H_VENV"
    "$BC6H_VENV/bin/pip" install --quiet --disable-pip-version-check imagecodecs==2026.3.6 ispc-texcomp==1.0.1 ||
        { echo "bc6h_independent_decoder: pip install imagecodecs ispc-texcomp failed (is PyPI reachable?)" >&2; exit 1; }
fi
source "$(dirname "$0")/ktx_parse.sh"

pairs=() sampled=()
for probe in sunsky sky room checker; do
    "$PROBEFILTER" synth $probe --size 32 --out "$work/$probe.exr" >/dev/null
    "$PROBEFILTER" filter "$work/$probe.exr" --size 32 --ktx2 bc6h --validate --out "$work/bc6h_$probe" >/dev/null
    "$PROBEFILTER" filter "$work/$probe.exr" --size 32 --ktx2 rgba16f --out "$work/half_$probe" >/dev/null
    KTX_PARSE_DIR="$node_dir" node "$root/tests/ktx2_bc6h_check.mjs" "$work/bc6h_$probe/probe.ktx2" "$work/bc6h_$probe/report.json"
    "$BC6H_SAMPLE" "$work/bc6h_$probe/probe.ktx2" "$work/sampled_$probe.raw" >/dev/null
    pairs+=("$work/bc6h_$probe/probe.ktx2" "$work/half_$probe/probe.ktx2")
    sampled+=(--sampled "$work/sampled_$probe.raw")
done
"$BC6H_VENV/bin/python" "$root/bench/scripts/bc6h.py" --min-margin -1 "${sampled[@]}" "${pairs[@]}"
