#!/usr/bin/env bash
# Checks the TextMate grammars of this folder: the generated files must match
# generate.mjs and the lexer's token table (crates/syntax/src/kinds.rs), and
# every vscode-tmgrammar-test fixture under tests/ must pass.
set -euo pipefail
cd "$(dirname "$0")"

fail() {
  echo "syntax/test.sh: FAILED: $1" >&2
  exit 1
}

command -v node >/dev/null 2>&1 || fail "node is not installed (Node.js 18 or later is needed)"
command -v npm >/dev/null 2>&1 || fail "npm is not installed"

if [ ! -x node_modules/.bin/vscode-tmgrammar-test ]; then
  npm ci --no-audit --no-fund || fail "npm ci could not install the test tools"
fi

node generate.mjs --check || fail "generated grammars are stale: run \`node syntax/generate.mjs\` and commit the result"
npm test --silent || fail "grammar tests (see the report above)"

fixtures=$(find tests -type f \( -name '*.rct' -o -name '*.rst' -o -name '*.assertions' -o -name '*.rsa' \) | wc -l)
assertions=$(cat tests/*/* | grep -cE '^//[[:space:]]*(\^|<~*-+)')
echo "syntax/test.sh: OK: ${fixtures// /} fixture files, ${assertions} scope assertions; grammars in sync with kinds.rs"
