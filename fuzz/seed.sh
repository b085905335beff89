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
# engine crate's tests are starting points.
out=corpus/verify
mkdir -p "$out"
find ../examples ../../shared/corpus -type f \( -name '*.rct' -o -name '*.rst' \) | while read -r f; do
  case "$f" in *.rct) sel='\x00' ;; *) sel='\x01' ;; esac
  { printf "$sel"; cat "$f"; } > "$out/$(echo "$f" | md5sum | cut -c1-16)"
done
# A design with what the engine runs alongside a state's substates: a
# composite state's during action and deadlines on transitions.
{ printf '\x00'; cat <<'RCT'
interface I { event e event v : nat op() op2(x : nat) }
stm M { uses I requires I var n : nat clock C
  initial i
  state S { during op(); wait(1); n = n + 1 initial j state A { entry op2(n) } state B { }
    transition x { from j to A } transition y { from A to B trigger v?n <{2} } }
  state T { entry wait([1, 2]) }
  transition t { from i to S action #C } transition u { from S to T trigger e <{3} condition since(C) < 3 }
  transition w { from T to S action #C } }
controller C { uses I requires I sref m = M connection C on e to m on e connection C on v to m on v }
module Mod { robotic platform P { uses I provides I } cref c = C
  connection P on e to c on e ( _async ) connection P on v to c on v ( _async ) }
RCT
} > "$out/activities"
# Controllers connected asynchronously (selector 2: a one-place buffer that
# overwrites) with a variable of the platform written by one machine and
# read by the other.
{ printf '\x02'; cat <<'RCT'
interface Out { event out : nat }
interface In { event inp : nat }
interface PV { var speed : nat }
stm Snd { uses Out requires PV initial i state A { entry out!1 ; speed = 1 ; out!2 } transition t { from i to A } }
stm M { uses In requires PV var x : nat
  initial i junction J state W { entry wait(1) } state G { }
  transition t0 { from i to W } transition t1 { from W to J trigger inp?x }
  transition g { from J to G condition x == speed } transition h { from J to W condition x != speed } }
controller CS { uses Out requires PV sref s = Snd connection s on out to CS on out }
controller CR { uses In requires PV sref r = M connection CR on inp to r on inp }
module Mod { robotic platform P { provides PV } cref cs = CS cref cr = CR
  connection cs on out to cr on inp ( _async ) }
RCT
} > "$out/async"
# A RoboSim module reading a variable of the platform and writing another.
{ printf '\x01'; cat <<'RST'
interface Lvl { var level : nat }
interface Alarm { var alarm : boolean }
stm W { cycleDef cycle == 1 input context { requires Lvl } output context { requires Alarm }
  initial i state S { } transition t0 { from i to S }
  transition hi { from S to S exec condition $level >= 2 action $alarm = true }
  transition lo { from S to S exec condition $level < 2 } }
controller C { cycleDef cycle == 1 requires Lvl requires Alarm sref w = W }
module Sim { cycleDef cycle == 1 robotic platform P { provides Lvl provides Alarm } cref c = C }
RST
} > "$out/platform-variables"
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
