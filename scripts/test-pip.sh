#!/usr/bin/env bash
# Tests `pip install` from this checkout without a network. Usage: scripts/test-pip.sh
# [build-dir]   (default: build, the build of scripts/build.sh; reused, so that only what it
# lacks is built)
#
# Makes a fresh virtual environment of Debian's /usr/bin/python3 with its site packages
# (NumPy, setuptools and wheel come from Debian), runs
#   pip install --no-build-isolation --no-index .
# in it with HEMIVEM_BUILD_DIR=build-dir, then, outside the checkout and without PYTHONPATH,
# imports hemivem and checks that the package and the hemivem libraries it loads come from
# the environment, and solves the default scene (converged, as `hemivem solve` finds it).
# Prints one line per check; exits 1 at the first failure.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
tmp="$(mktemp -d "${TMPDIR:-/tmp}/hemivem-pip.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT

fail() { echo "test-pip: FAIL: $*" >&2; exit 1; }
ok() { echo "test-pip: ok: $*"; }

/usr/bin/python3 -m venv --system-site-packages "$tmp/venv" >"$tmp/venv.log" 2>&1 ||
  { cat "$tmp/venv.log"; fail "python3 -m venv (Debian: python3-venv)"; }
python="$tmp/venv/bin/python"
if ! (cd "$root" && env -u PYTHONPATH HEMIVEM_BUILD_DIR="$build" PIP_NO_CACHE_DIR=1 \
        "$python" -m pip install --no-build-isolation --no-index . >"$tmp/pip.log" 2>&1); then
  tail -40 "$tmp/pip.log"
  fail "pip install --no-build-isolation --no-index ."
fi
ok "pip install --no-build-isolation --no-index . into a fresh virtual environment"

cd "$tmp"
env -u PYTHONPATH -u HEMIVEM_BUILD_DIR "$python" - "$tmp/venv" "$build/drivers/hemivem" <<'PY' || fail "the installed package (above)"
import json, os, pathlib, subprocess, sys, tempfile
venv = pathlib.Path(sys.argv[1]).resolve()
import hemivem
where = pathlib.Path(hemivem.__file__).resolve()
assert venv in where.parents, f"hemivem imported from {where}, not from {venv}"
with open("/proc/self/maps") as maps:
    libraries = {line.split()[-1] for line in maps if "libhemivem" in line or "_hemivem" in line}
outside = [lib for lib in libraries if venv not in pathlib.Path(lib).resolve().parents]
assert libraries and not outside, f"hemivem libraries loaded from outside {venv}: {outside}"
print(f"test-pip: ok: hemivem {hemivem.__version__} and its {len(libraries)} libraries load from the environment")
r = hemivem.solve(hemivem.Scene.default())
assert r.converged, r.status
with tempfile.TemporaryDirectory() as out:
    p = subprocess.run([sys.argv[2], "solve", "--out", out], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    j = json.loads(pathlib.Path(out, "result.json").read_text())
assert r.energy == j["potential_energy"], (r.energy, j["potential_energy"])
print(f"test-pip: ok: the default scene solved: {r.status}, energy {r.energy} as the command's")
PY
