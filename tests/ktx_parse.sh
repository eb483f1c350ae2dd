# Sourced by the tests that check KTX2 with the independent parser ktx-parse: installs it with npm
# into $KTX_PARSE_PREFIX on first use and sets node_dir to the node_modules folder that holds it.
node_dir="${KTX_PARSE_PREFIX:?}/node_modules"
if [[ ! -d $node_dir/ktx-parse ]]; then
    npm install --silent --no-audit --no-fund --prefix "$KTX_PARSE_PREFIX" ktx-parse@2.0.0 >/dev/null ||
        { echo "$(basename "$0" .sh): npm install ktx-parse@2.0.0 failed (is the npm registry reachable?)" >&2; exit 1; }
fi
