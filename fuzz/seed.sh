#!/usr/bin/env bash
# Fills fuzz/corpus/parse with seeds: every model of ../shared/corpus, our
# examples and parser fixtures, plus a few hostile shapes.
set -euo pipefail
cd "$(dirname "$0")"
out=corpus/parse
mkdir -p "$out"
find ../../shared/corpus ../examples ../crates/syntax/test_data ../crates/stdlib/lib \
  -type f \( -name '*.rct' -o -name '*.rst' -o -name '*.assertions' -o -name '*.rsa' \) |
  while read -r f; do cp "$f" "$out/$(echo "$f" | md5sum | cut -c1-16)"; done
python3 - "$out" <<'PY'
import sys, os
out = sys.argv[1]
open(os.path.join(out, "nested"), "w").write("function f() : int { postcondition " + "(" * 5000 + "1" + ")" * 5000 + " }")
open(os.path.join(out, "longline"), "w").write("interface I { var x : int = " + "1 + " * 10000 + "1 }")
PY
echo "$(ls "$out" | wc -l) seeds in fuzz/$out"

# fuzz/corpus/verify: models whose first byte selects .rct (even) or .rst
# (odd), checked against the fixed assertions of fuzz_targets/verify.rs
# (which name `Mod`, `M` and `Sim`): our examples and every .rct/.rst of the
# check crate's tests are starting points.
out=corpus/verify
mkdir -p "$out"
find ../examples ../../shared/corpus -type f \( -name '*.rct' -o -name '*.rst' \) | while read -r f; do
  case "$f" in *.rct) sel='\x00' ;; *) sel='\x01' ;; esac
  { printf "$sel"; cat "$f"; } > "$out/$(echo "$f" | md5sum | cut -c1-16)"
done
echo "$(ls "$out" | wc -l) seeds in fuzz/$out"

# fuzz/corpus/reparse: each model with a four-byte edit header (position,
# deleted length, inserted length; see fuzz_targets/reparse.rs) that puts
# the edit about a third of the way in, inserting nothing.
out=corpus/reparse
mkdir -p "$out"
find ../examples ../../shared/corpus -type f \( -name '*.rct' -o -name '*.rst' \) | while read -r f; do
  pos=$(( $(wc -c < "$f") / 3 % 65536 ))
  { printf "\\x$(printf %02x $((pos % 256)))\\x$(printf %02x $((pos / 256)))\\x01\\x00"; cat "$f"; } > "$out/$(echo "$f" | md5sum | cut -c1-16)"
done
echo "$(ls "$out" | wc -l) seeds in fuzz/$out"
