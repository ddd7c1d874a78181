#!/usr/bin/env bash
# Tests the installed package. Usage: scripts/test-install.sh [build-dir]   (default: build)
#
# Installs the build into a fresh temporary prefix and, against that prefix only,
#   1. compiles every installed header on its own with the prefix and Eigen as the only
#      include paths, and checks that none pulls in a file of an engine's package;
#   2. configures, builds and runs examples/step-by-step (the library's pieces) and
#      examples/host-app (a scene to result.json with hemivem::app), and checks that their
#      answers are the installed command's;
#   3. runs the installed command with the mumps-mpi engine (when built) and checks that the
#      module is loaded from the prefix;
#   4. checks that a component that is unknown, or known but not built, stops the
#      configuration of a project with a message naming it and listing those that were
#      built, and that an optional one only sets hemivem_<component>_FOUND to false.
#   5. imports the installed Python package (when the module was built) with the build's
#      interpreter and only the prefix on PYTHONPATH, checks that it and the libraries it
#      loads come from the prefix, and that its solve is the installed command's.
# Prints one line per check; exits 1 at the first failure.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
tmp="$(mktemp -d "${TMPDIR:-/tmp}/hemivem-install.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"

fail() { echo "test-install: FAIL: $*" >&2; exit 1; }
ok() { echo "test-install: ok: $*"; }
cache() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }

cmake --install "$build" --prefix "$prefix" >"$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install"; }
config="$(find "$prefix" -name hemivemConfig.cmake -print -quit)"
[ -n "$config" ] || fail "no hemivemConfig.cmake under $prefix"
configdir="$(dirname "$config")"
for f in hemivemConfigVersion.cmake hemivemTargets.cmake FindCHOLMOD.cmake FindMUMPS.cmake; do
  [ -f "$configdir/$f" ] || fail "$f not installed in $configdir"
done
[ -x "$prefix/bin/hemivem" ] || fail "bin/hemivem not installed"
built="$(sed -n 's/^set(hemivem_COMPONENTS "\(.*\)")$/\1/p' "$config")"
[ -n "$built" ] || fail "hemivemConfig.cmake lists no components"
has() { case ";$built;" in *";$1;"*) return 0 ;; *) return 1 ;; esac; }
ok "installed into a fresh prefix ($(find "$prefix" -type f | wc -l) files; components $built)"

# Only the temporary prefix: no package registry, no other prefix, no build tree.
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
isolated=("${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix"
          -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF
          -DCMAKE_EXPORT_NO_PACKAGE_REGISTRY=ON -DCMAKE_CXX_COMPILER="$(cache CMAKE_CXX_COMPILER)")

# ---- 1. headers -------------------------------------------------------------------------
cxx="$(cache CMAKE_CXX_COMPILER)"
eigen="$(pkg-config --cflags-only-I eigen3 2>/dev/null | sed 's/^ *-I//; s/ *$//')"
[ -n "$eigen" ] || eigen=/usr/include/eigen3
[ -f "$eigen/Eigen/Core" ] || fail "Eigen not found (looked in $eigen)"
export cxx eigen prefix tmp
check_header() {
  local header name
  header="${1#"$prefix/include/"}"
  name="$(echo "${header%.hpp}" | tr '/' '_')"
  printf '#include <%s>\n' "$header" >"$tmp/h_$name.cpp"
  if ! "$cxx" -std=c++20 -fsyntax-only -Wall -Wextra -I"$prefix/include" -I"$eigen" \
       -MD -MF "$tmp/h_$name.d" "$tmp/h_$name.cpp" 2>"$tmp/h_$name.err"; then
    echo "$header does not compile on its own:"; head -20 "$tmp/h_$name.err"; return 1
  fi
  # Every file it includes, outside the prefix and Eigen, must be the compiler's or libc's.
  tr ' \\' '\n\n' <"$tmp/h_$name.d" | sed '/^$/d;/:$/d' |
    grep -v -e "^$prefix/" -e "^$eigen/" -e "h_$name.cpp" >"$tmp/h_$name.deps" || true
  if grep -E -i 'cholmod|suitesparse|mumps|mpi\.h|nlopt|ceres|cgal|toml|boost|gmp' "$tmp/h_$name.deps"; then
    echo "$header includes a file of an engine's package (above)"; return 1
  fi
}
export -f check_header
mapfile -t headers < <(find "$prefix/include/hemivem" -name '*.hpp' | sort)
[ "${#headers[@]}" -ge 20 ] || fail "only ${#headers[@]} headers installed"
printf '%s\n' "${headers[@]}" | xargs -P 2 -I{} bash -c 'check_header "$1"' _ {} ||
  fail "installed headers (see above)"
ok "${#headers[@]} installed headers compile on their own with only the prefix and Eigen, none includes an engine's package"

# ---- 2. the host applications ------------------------------------------------------------
if ! has cholmod; then
  echo "test-install: skipped: examples/step-by-step needs the component cholmod, which was not built"
else
  cmake -S "$root/examples/step-by-step" -B "$tmp/step-build" "${isolated[@]}" >"$tmp/step-configure.log" 2>&1 ||
    { cat "$tmp/step-configure.log"; fail "configuring examples/step-by-step against $prefix"; }
  found="$(sed -n 's/^hemivem_DIR:PATH=//p' "$tmp/step-build/CMakeCache.txt")"
  [ "$found" = "$configdir" ] || fail "examples/step-by-step found hemivem in '$found', not in $configdir"
  cmake --build "$tmp/step-build" >"$tmp/step-build.log" 2>&1 || { cat "$tmp/step-build.log"; fail "building examples/step-by-step"; }
  if ldd "$tmp/step-build/step-by-step" | grep -E 'libhemivem_(linear|nonsmooth)(\.so| )' ; then
    fail "step-by-step links a factory although it names only cholmod and ssn"
  fi
  status=0
  "$tmp/step-build/step-by-step" >"$tmp/host.out" 2>&1 || status=$?
  cat "$tmp/host.out"
  [ "$status" -eq 0 ] || fail "step-by-step exited with $status"
  grep -q 'minimizer     ssn: converged' "$tmp/host.out" || fail "step-by-step did not report convergence"
  # Its contact nodes are those of the installed command on the same problem.
  "$prefix/bin/hemivem" solve --n 32 --linear cholmod --minimizer ssn --out "$tmp/solve32" >"$tmp/cli.out" 2>/dev/null ||
    fail "installed hemivem solve --n 32 failed"
  host_contact="$(sed -n 's/^ *contact *//p' "$tmp/host.out")"
  cli_contact="$(sed -n 's/^ *contact *//p' "$tmp/cli.out")"
  [ -n "$host_contact" ] && [ "$host_contact" = "$cli_contact" ] ||
    fail "step-by-step contact '$host_contact' differs from hemivem solve's '$cli_contact'"
  ok "examples/step-by-step built against the prefix only ($found), converged, same contact nodes as hemivem solve"
fi

# A scene file to result.json with hemivem::app: the installed command's result.
scene="$root/scenes/paper-example-4.1.toml"
cmake -S "$root/examples/host-app" -B "$tmp/host-build" "${isolated[@]}" >"$tmp/host-configure.log" 2>&1 ||
  { cat "$tmp/host-configure.log"; fail "configuring examples/host-app against $prefix"; }
cmake --build "$tmp/host-build" >"$tmp/host-build.log" 2>&1 || { cat "$tmp/host-build.log"; fail "building examples/host-app"; }
status=0
"$tmp/host-build/host-app" "$scene" "$tmp/host-out" >"$tmp/host.out" 2>&1 || status=$?
cat "$tmp/host.out"
[ "$status" -eq 0 ] || fail "host-app exited with $status"
"$prefix/bin/hemivem" solve "$scene" --out "$tmp/cli-out" -q >/dev/null 2>&1 || fail "installed hemivem solve failed"
python3 - "$tmp/host-out/result.json" "$tmp/cli-out/result.json" <<'PY' || fail "host-app's result.json differs from hemivem solve's"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
for key in ("status", "certificate", "potential_energy", "contact_zone", "iterations"):
    if a[key] != b[key]:
        sys.exit(f"{key}: {a[key]} != {b[key]}")
PY
cmp -s "$tmp/host-out/displacement.csv" "$tmp/cli-out/displacement.csv" ||
  fail "host-app's displacement.csv differs from hemivem solve's"
ok "examples/host-app: a scene to result.json with hemivem::app, the same certificate, energy and displacement as hemivem solve"

# ---- 3. the mumps-mpi module from the prefix ----------------------------------------------
if has mumps-mpi; then
  plugin="$(find "$prefix" -name 'libhemivem_linear_mumps_mpi_plugin*' -print -quit)"
  [ -n "$plugin" ] || fail "the mumps-mpi module is not installed"
  env -u HEMIVEM_MUMPS_MPI_PLUGIN LD_DEBUG=files "$prefix/bin/hemivem" solve --n 8 --linear mumps-mpi \
    --out "$tmp/solve-mpi" >"$tmp/mpi.out" 2>"$tmp/mpi.err" || { tail -5 "$tmp/mpi.err"; fail "installed hemivem with --linear mumps-mpi"; }
  loaded="$(sed -n 's/.*file=\([^ ]*mumps_mpi_plugin[^ ]*\) .*dynamically loaded.*/\1/p' "$tmp/mpi.err" | head -1)"
  [ -n "$loaded" ] && [ "$(realpath "$loaded")" = "$(realpath "$plugin")" ] ||
    fail "the installed command loaded the mumps-mpi module from '$loaded', not $plugin"
  grep -q 'status *converged' "$tmp/mpi.out" || fail "installed hemivem with --linear mumps-mpi did not converge"
  ok "the installed command loads the mumps-mpi module from $plugin"
fi

# ---- 4. components ------------------------------------------------------------------------
missing=""
known="$(sed -n 's/^set(_hemivem_known "\(.*\)")$/\1/p' "$config")"
[ -n "$known" ] || fail "hemivemConfig.cmake lists no known components"
for c in ${known//;/ }; do
  has "$c" || missing="$c"
done
for wanted in no-such-engine $missing; do
  mkdir -p "$tmp/components-$wanted"
  cat >"$tmp/components-$wanted/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.25)
project(components LANGUAGES CXX)
find_package(hemivem CONFIG REQUIRED COMPONENTS ssn $wanted)
EOF
  if cmake -S "$tmp/components-$wanted" -B "$tmp/components-$wanted/build" "${isolated[@]}" >"$tmp/components.log" 2>&1; then
    fail "find_package(hemivem COMPONENTS ssn $wanted) succeeded"
  fi
  message="$(tr '\n' ' ' <"$tmp/components.log" | tr -s ' ')"
  case "$message" in
    *"'$wanted'"*"components built: ${built//;/, }"*) ;;
    *) cat "$tmp/components.log"; fail "the message for component '$wanted' does not name it and list those built" ;;
  esac
  ok "find_package(hemivem REQUIRED COMPONENTS ssn $wanted) fails at configure time naming '$wanted'"
done
mkdir -p "$tmp/optional"
cat >"$tmp/optional/CMakeLists.txt" <<'EOF'
cmake_minimum_required(VERSION 3.25)
project(optional LANGUAGES CXX)
find_package(hemivem CONFIG REQUIRED COMPONENTS linear nonsmooth global-search OPTIONAL_COMPONENTS no-such-engine)
if(NOT hemivem_FOUND OR NOT hemivem_linear_FOUND OR NOT DEFINED hemivem_no-such-engine_FOUND OR hemivem_no-such-engine_FOUND)
  message(FATAL_ERROR "hemivem_FOUND=${hemivem_FOUND} hemivem_no-such-engine_FOUND=${hemivem_no-such-engine_FOUND}")
endif()
file(WRITE ${CMAKE_BINARY_DIR}/main.cpp [=[
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/global_search.hpp>
#include <cstdio>
int main() {
  for (const auto& name : hemivem::available_factorizations()) std::printf("%s ", name.c_str());
  for (const auto& name : hemivem::available_minimizers()) std::printf("%s ", name.c_str());
  std::printf("\n");
  const auto search = hemivem::make_global_search("ssn");
  return hemivem::make_factorization({.engine = "eigen"})->name() == "eigen" && search->engine_names().front() == "ssn" ? 0 : 1;
}
]=])
add_executable(factories ${CMAKE_BINARY_DIR}/main.cpp)
target_link_libraries(factories PRIVATE hemivem::linear hemivem::nonsmooth hemivem::global_search)
EOF
cmake -S "$tmp/optional" -B "$tmp/optional/build" "${isolated[@]}" >"$tmp/optional.log" 2>&1 ||
  { cat "$tmp/optional.log"; fail "OPTIONAL_COMPONENTS no-such-engine"; }
cmake --build "$tmp/optional/build" >"$tmp/optional-build.log" 2>&1 || { cat "$tmp/optional-build.log"; fail "building against hemivem::linear, hemivem::nonsmooth and hemivem::global_search"; }
engines="$("$tmp/optional/build/factories")" || fail "a program linking the factories failed"
ok "an optional unknown component sets hemivem_no-such-engine_FOUND false; the factories and the global search link; built: $engines"

# ---- 5. the Python package from the prefix ------------------------------------------------
pydir="$(cache HEMIVEM_PYTHON_INSTALL_DIR)"
if [ "$(cache HEMIVEM_BUILD_PYTHON)" != ON ] || [ -z "$pydir" ] ||
   ! compgen -G "$build/python/hemivem/_hemivem*.so" >/dev/null; then
  echo "test-install: skipped: the Python module was not built"
else
  python="$(cache Python3_EXECUTABLE)"
  [ -x "$python" ] || fail "the interpreter the Python module was built for, '$python', is missing"
  site="$prefix/$pydir"
  compgen -G "$site/hemivem/_hemivem*.so" >/dev/null || fail "the Python module is not installed in $site/hemivem"
  "$prefix/bin/hemivem" solve --n 8 --out "$tmp/solve-py" -q || fail "installed hemivem solve --n 8 failed"
  # A clean environment: no LD_LIBRARY_PATH, no user site, not run from the source tree.
  cat >"$tmp/installed.py" <<'EOF'
import json, os, sys
prefix = os.path.realpath(sys.argv[1])
import hemivem
for m in (hemivem, hemivem._hemivem):
    if not os.path.realpath(m.__file__).startswith(prefix + "/"):
        sys.exit(f"{m.__name__} imported from {m.__file__}, not from {prefix}")
with open("/proc/self/maps") as f:
    loaded = {line.split()[-1] for line in f if "/" in line and "hemivem" in line.rsplit("/", 1)[-1]}
outside = sorted(p for p in loaded if not os.path.realpath(p).startswith(prefix + "/"))
if outside:
    sys.exit(f"libraries loaded from outside the prefix: {', '.join(outside)}")
scene = hemivem.Scene.default()
scene.set("mesh.n", 8)
r = hemivem.solve(scene)
with open(sys.argv[2]) as f:
    expected = json.load(f)
u_nu = [n["u_nu"] for n in expected["contact"]]
scale = max(abs(x) for x in u_nu)
if (r.status != expected["status"] or len(r.contact) != len(u_nu)
        or abs(r.energy - expected["potential_energy"]) > 1e-12 * abs(r.energy)
        or max(abs(a - b) for a, b in zip(r.contact.u_nu, u_nu)) > 1e-12 * scale):
    sys.exit(f"the package's solve ({r}) differs from the installed command's result.json")
print(f"{len(loaded)} hemivem libraries loaded, all from the prefix; {r.status}, energy {r.energy:.12g}")
EOF
  (cd "$tmp" && env -i PATH=/usr/bin:/bin HOME="$tmp" PYTHONNOUSERSITE=1 PYTHONPATH="$site" \
     "$python" "$tmp/installed.py" "$prefix" "$tmp/solve-py/result.json") >"$tmp/python.out" 2>&1 ||
    { cat "$tmp/python.out"; fail "the Python package installed in $site"; }
  ok "the Python package imports from $site alone ($python): $(tail -1 "$tmp/python.out"), as the installed command"
fi
