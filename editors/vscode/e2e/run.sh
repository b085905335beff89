#!/usr/bin/env bash
# End-to-end test of the VS Code extension in a real VS Code workbench:
# code-server (VS Code 1.100.3 with the ordinary Node extension host) driven
# by headless Chromium through playwright-core, as a person would use it.
#
# It packages the .vsix as a user builds it (`npm ci`, `npm run package` in
# editors/vscode), installs it into code-server with a fresh profile, points
# `robosim.server.path` at ROBOSIM_BIN, opens a workspace of example models
# and checks the features in the UI (test.mjs). Screenshots of every step go
# to target/vscode-e2e/shots/ (under CARGO_TARGET_DIR if set); the profile,
# with the logs of the extension host and of the server's trace, stays in
# target/vscode-e2e/state/ until the next run.
#
# ROBOSIM_BIN names the server binary; when unset, it is built with cargo.
# Installs what it needs: Chromium, a C++ toolchain, libkrb5-dev and ripgrep
# with apt-get (as root, or through sudo), then its Node packages with
# `npm ci` (code-server builds native modules with node-gyp). Offline but for
# the package registries. Serves on 127.0.0.1 only and stops every process
# it started.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
ext="$(cd "$here/.." && pwd)"
repo="$(cd "$here/../../.." && pwd)"
out="${CARGO_TARGET_DIR:-$repo/target}/vscode-e2e"

fail() {
  echo "vscode-e2e: FAILED: $1" >&2
  echo "vscode-e2e: 0 passed, 1 failed"
  exit 1
}

# --- System packages -------------------------------------------------------
need=()
# chromium: the browser; g++, make, python3 (node-gyp) and libkrb5-dev (the
# `kerberos` module): code-server's native modules; ripgrep: see below.
for p in chromium g++ make python3 libkrb5-dev ripgrep fonts-dejavu-core; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || need+=("$p")
done
if [ "${#need[@]}" -gt 0 ]; then
  echo "vscode-e2e: installing ${need[*]} with apt-get"
  if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
  $sudo apt-get update -qq || fail "apt-get update"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null \
    || fail "apt-get install ${need[*]}"
fi

command -v node >/dev/null 2>&1 || fail "node is not installed"
major="$(node -p 'process.versions.node.split(".")[0]')"
# code-server 4.100.3 is the newest release whose install accepts Node 20.
[ "$major" = 20 ] || fail "code-server 4.100.3 installs only with Node.js 20, not $(node --version)"
# node-gyp builds against the headers of the installed Node (no download).
nodedir="$(cd "$(dirname "$(readlink -f "$(command -v node)")")/.." && pwd)"
[ -e "$nodedir/include/node/node.h" ] \
  || fail "Node's headers ($nodedir/include/node/node.h) are missing: install the nodejs package that ships them"

# --- Node packages -----------------------------------------------------------
# Installed outside editors/vscode (vsce would walk a node_modules there on
# every `npm run package`), from this folder's package.json and lock file.
node_dir="$out/node"
if [ ! -x "$node_dir/node_modules/.bin/code-server" ] || [ ! -d "$node_dir/node_modules/playwright-core" ] \
  || [ ! -e "$node_dir/node_modules/code-server/lib/vscode/node_modules/@vscode/ripgrep/bin/rg" ] \
  || ! cmp -s "$here/package-lock.json" "$node_dir/package-lock.json"; then
  rm -rf "$node_dir"
  mkdir -p "$node_dir"
  cp "$here/package.json" "$here/package-lock.json" "$node_dir/"
  # @vscode/ripgrep (a dependency of code-server's VS Code) downloads rg in
  # its install script unless the archive is in its cache, under TMPDIR: the
  # archive it expects, with Debian's rg in it. Both names follow the
  # versions that code-server 4.100.3's shrinkwrap pins.
  cache="$node_dir/.install"
  mkdir -p "$cache/tmp/vscode-ripgrep-cache-1.15.11" "$cache/rg"
  cp "$(command -v rg)" "$cache/rg/rg"
  tar czf "$cache/tmp/vscode-ripgrep-cache-1.15.11/ripgrep-v13.0.0-10-x86_64-unknown-linux-musl.tar.gz" -C "$cache/rg" rg
  echo "vscode-e2e: npm ci (code-server builds its native modules; about a minute)"
  # npm_config_yes: code-server's install runs `npx node-gyp`; unsafe_perm:
  # it refuses to install as root without it.
  (cd "$node_dir" && TMPDIR="$cache/tmp" npm_config_yes=true npm_config_unsafe_perm=true npm_config_nodedir="$nodedir" \
    npm ci --no-audit --no-fund >"$cache/npm-ci.log" 2>&1) || {
    tail -40 "$cache/npm-ci.log" >&2
    rm -f "$node_dir/package-lock.json" # install again next time
    fail "npm ci of editors/vscode/e2e/package-lock.json (log: $cache/npm-ci.log)"
  }
fi

# --- The .vsix, as a user builds it -----------------------------------------
if [ ! -x "$ext/node_modules/.bin/tsc" ] || [ ! -f "$ext/node_modules/@vscode/vsce/vsce" ] \
  || [ "$ext/package-lock.json" -nt "$ext/node_modules/.package-lock.json" ]; then
  (cd "$ext" && npm ci --no-audit --no-fund) || fail "npm ci in editors/vscode"
fi
(cd "$ext" && npm run package >/dev/null) || fail "npm run package in editors/vscode"
vsix="$ext/dist/$(node -p 'const p = require(process.argv[1]); `${p.name}-${p.version}.vsix`' "$ext/package.json")"
[ -f "$vsix" ] || fail "no $vsix after npm run package"

# --- The server -----------------------------------------------------------------
if [ -z "${ROBOSIM_BIN:-}" ]; then
  (cd "$repo" && cargo build --locked -q -p robosim-cli) || fail "cargo build -p robosim-cli"
  ROBOSIM_BIN="${CARGO_TARGET_DIR:-$repo/target}/debug/robosim"
fi
case "$ROBOSIM_BIN" in
  /*) ;;
  *) ROBOSIM_BIN="$(cd "$(dirname "$ROBOSIM_BIN")" && pwd)/$(basename "$ROBOSIM_BIN")" ;;
esac
[ -x "$ROBOSIM_BIN" ] || fail "ROBOSIM_BIN=$ROBOSIM_BIN is not an executable file"

# --- A fresh profile and workspace -------------------------------------------
rm -rf "$out/shots" "$out/state" "$out"/*.log "$out"/*.txt
mkdir -p "$out/shots"
state="$out/state" # profile, extensions and the workspace copy
mkdir -p "$state/config" "$state/data" "$state/user-data/User" "$state/extensions" "$state/tmp"
# code-server writes to ~/.config and ~/.local/share even with
# --user-data-dir; keep it all inside the test's folder.
export XDG_CONFIG_HOME="$state/config" XDG_DATA_HOME="$state/data" TMPDIR="$state/tmp"
workspace="$state/workspace"
mkdir -p "$workspace"
cp -r "$repo/examples/paper" "$workspace/paper"
cp -r "$here/workspace/." "$workspace/"

cs=("$node_dir/node_modules/.bin/code-server" --user-data-dir "$state/user-data" --extensions-dir "$state/extensions")
timeout 120 "${cs[@]}" --install-extension "$vsix" >"$out/install.log" 2>&1 || {
  cat "$out/install.log" >&2
  fail "code-server --install-extension $vsix"
}
timeout 60 "${cs[@]}" --list-extensions >"$out/extensions.txt" 2>&1 || true
grep -qx "robosim.robosim" "$out/extensions.txt" || {
  cat "$out/extensions.txt" >&2
  fail "robosim.robosim is not listed after --install-extension"
}
node -e '
  const [file, bin] = process.argv.slice(1);
  require("fs").writeFileSync(file, JSON.stringify({
    "robosim.server.path": bin,
    "workbench.startupEditor": "none",
    "workbench.tips.enabled": false,
    "workbench.enableExperiments": false,
    "extensions.autoCheckUpdates": false,
    "extensions.autoUpdate": false,
    "update.mode": "none",
    "telemetry.telemetryLevel": "off",
    "security.workspace.trust.enabled": false,
    "editor.minimap.enabled": false,
    "editor.hover.delay": 300,
    "editor.codeLens": true,
    "files.autoSave": "off",
    "window.restoreWindows": "none",
    "robosim.trace.server": "messages",
    "git.enabled": false,
    "git.openRepositoryInParentFolders": "never",
  }, null, 2));
' "$state/user-data/User/settings.json" "$ROBOSIM_BIN"

# --- code-server, in a process group of its own --------------------------------
port="$(node -e 'const s = require("net").createServer().listen(0, "127.0.0.1", () => { console.log(s.address().port); s.close(); })')"
pgid=""
cleanup() {
  if [ -n "$pgid" ]; then
    kill -TERM -- "-$pgid" 2>/dev/null || true
    for _ in 1 2 3 4 5 6 7 8 9 10; do
      kill -0 -- "-$pgid" 2>/dev/null || break
      sleep 0.3
    done
    kill -KILL -- "-$pgid" 2>/dev/null || true
  fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM
setsid "${cs[@]}" --bind-addr "127.0.0.1:$port" --auth none --disable-telemetry --disable-update-check \
  --disable-workspace-trust --disable-getting-started-override --ignore-last-opened "$workspace" \
  >"$out/code-server.log" 2>&1 </dev/null &
pgid=$! # setsid (not a group leader here, so it does not fork) makes code-server one
# The forked shell runs setsid a moment after `&` returns.
for _ in $(seq 1 50); do
  [ "$(ps -o pgid= -p "$pgid" | tr -d ' ')" = "$pgid" ] && break
  sleep 0.1
done
[ "$(ps -o pgid= -p "$pgid" | tr -d ' ')" = "$pgid" ] || fail "code-server is not the leader of its process group"
for _ in $(seq 1 120); do
  grep -q "HTTP server listening" "$out/code-server.log" 2>/dev/null && break
  kill -0 "$pgid" 2>/dev/null || break
  sleep 0.5
done
grep -q "HTTP server listening" "$out/code-server.log" || {
  cat "$out/code-server.log" >&2
  fail "code-server did not start listening on 127.0.0.1:$port"
}

status=0
VSCODE_E2E_URL="http://127.0.0.1:$port/?folder=$workspace" VSCODE_E2E_WORKSPACE="$workspace" \
  VSCODE_E2E_NODE="$node_dir" VSCODE_E2E_SHOTS="$out/shots" VSCODE_E2E_SETTINGS="$state/user-data/User/settings.json" \
  timeout 600 node "$here/test.mjs" || status=$?
# test.mjs prints `vscode-e2e: N passed, M failed`; a crash before it did not.
if [ "$status" -ne 0 ] && [ "$status" -ne 1 ]; then
  echo "vscode-e2e: test.mjs exited with status $status"
  echo "vscode-e2e: 0 passed, 1 failed"
fi
echo "vscode-e2e: screenshots in $out/shots"
exit "$status"
