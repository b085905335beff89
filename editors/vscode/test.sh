#!/usr/bin/env bash
# Tests the VS Code extension without VS Code: type-check, bundle, package the
# .vsix and check its contents, unit-test the extension's logic, and drive
# the real `robosim lsp` binary over stdio with vscode-languageserver-protocol.
#
# ROBOSIM_BIN names the server binary; when it is unset, the script builds it
# (`cargo build -p robosim-cli`) and uses target/debug/robosim (under
# CARGO_TARGET_DIR if that is set). Non-interactive; safe to run again.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
cd "$here"

fail() {
  echo "editors/vscode/test.sh: FAILED: $1" >&2
  exit 1
}

command -v node >/dev/null 2>&1 || fail "node is not installed (Node.js 20 or later is needed)"
command -v npm >/dev/null 2>&1 || fail "npm is not installed"
major="$(node -p 'process.versions.node.split(".")[0]')"
[ "$major" -ge 20 ] || fail "Node.js $(node --version) is too old: @vscode/vsce 3.9 needs Node.js 20 or later"

# Install when node_modules is missing, incomplete or older than the lock file.
if [ ! -x node_modules/.bin/tsc ] || [ ! -f node_modules/@vscode/vsce/vsce ] \
  || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  npm ci --no-audit --no-fund || fail "npm ci could not install the packages of package-lock.json"
fi

if [ -z "${ROBOSIM_BIN:-}" ]; then
  command -v cargo >/dev/null 2>&1 || fail "cargo is not installed; set ROBOSIM_BIN to a robosim binary instead"
  (cd "$repo" && cargo build --locked -p robosim-cli) || fail "cargo build -p robosim-cli"
  export ROBOSIM_BIN="${CARGO_TARGET_DIR:-$repo/target}/debug/robosim"
fi
case "$ROBOSIM_BIN" in
  /*) ;;
  *) ROBOSIM_BIN="$(cd "$(dirname "$ROBOSIM_BIN")" && pwd)/$(basename "$ROBOSIM_BIN")" ;;
esac
export ROBOSIM_BIN
[ -x "$ROBOSIM_BIN" ] || fail "ROBOSIM_BIN=$ROBOSIM_BIN is not an executable file"
echo "editors/vscode/test.sh: server binary $ROBOSIM_BIN"

log="$(mktemp)"
trap 'rm -f "$log"' EXIT
status=0
npm test 2>&1 | tee "$log" || status=$?

# One closing line from node's test runner summary (TAP: `# pass N`,
# `# fail M`, `# cancelled K`; cancelled tests count as failed).
passed="$(awk '/^# pass / { s += $3 } END { print s + 0 }' "$log")"
failed="$(awk '/^# (fail|cancelled) / { s += $3 } END { print s + 0 }' "$log")"
skipped="$(awk '/^# skipped / { s += $3 } END { print s + 0 }' "$log")"
if [ "$status" -ne 0 ] && [ "$failed" -eq 0 ]; then
  # A step before the Node tests (type-check, bundle, package) failed.
  failed=1
fi
echo "vscode: $passed passed, $failed failed, $skipped skipped"
exit "$status"
