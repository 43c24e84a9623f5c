# Sourced by the POV-Ray comparisons once they have set `root`, `out` and `glint`:
# stops when POV-Ray is missing, builds glint when its binary is, and makes `out`.
if ! command -v povray >/dev/null; then
    echo "povray is not installed; on Debian/Ubuntu: apt-get install -y povray" >&2
    exit 1
fi
if [[ ! -x "$glint" ]]; then
    (cd "$root" && cargo build --release -p glint-cli)
fi
mkdir -p "$out"
