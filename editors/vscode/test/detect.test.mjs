// The extension's vscode-free logic, bundled by scripts/build.mjs into
// out/test/: finding the server binary, and deciding whether a `.rst` file
// is RoboSim.
import assert from "node:assert/strict";
import { readdirSync, readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, join } from "node:path";
import { test } from "node:test";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const require = createRequire(import.meta.url);
const { resolveServer, searchPath } = require(join(root, "out", "test", "server-path.js"));
const { looksLikeRoboSim, userAssociation, globToRegExp, RstSwitcher } = require(join(root, "out", "test", "rst-detect.js"));
const fixtures = join(root, "..", "testdata", "filetype");

// --- finding the server -----------------------------------------------------

const files = (list) => (f) => list.includes(f);

test("server: the setting wins over the bundled binary and PATH", () => {
  const r = resolveServer({
    configured: "/opt/robosim/bin/robosim",
    extensionPath: "/ext",
    platform: "linux",
    pathVariable: "/usr/bin",
    isExecutableFile: files(["/opt/robosim/bin/robosim", "/ext/server/robosim", "/usr/bin/robosim"]),
  });
  assert.deepEqual(r, { ok: true, command: "/opt/robosim/bin/robosim", source: "setting" });
});

test("server: `~/` in the setting is the home folder; a bare name is looked up on PATH", () => {
  const home = resolveServer({
    configured: "~/.cargo/bin/robosim",
    extensionPath: "/ext",
    platform: "linux",
    homeDir: "/home/ada",
    pathVariable: "",
    isExecutableFile: files(["/home/ada/.cargo/bin/robosim"]),
  });
  assert.deepEqual(home, { ok: true, command: "/home/ada/.cargo/bin/robosim", source: "setting" });
  const bare = resolveServer({
    configured: "robosim-nightly",
    extensionPath: "/ext",
    platform: "linux",
    pathVariable: "/a:/b",
    isExecutableFile: files(["/b/robosim-nightly"]),
  });
  assert.deepEqual(bare, { ok: true, command: "/b/robosim-nightly", source: "setting" });
});

test("server: a setting naming a missing file is an error, with no silent fallback", () => {
  const r = resolveServer({
    configured: "/nope/robosim",
    extensionPath: "/ext",
    platform: "linux",
    pathVariable: "/usr/bin",
    isExecutableFile: files(["/ext/server/robosim", "/usr/bin/robosim"]),
  });
  assert.equal(r.ok, false);
  assert.equal(r.reason, "setting-not-found");
  assert.match(r.message, /robosim\.server\.path is set to "\/nope\/robosim"/);
  const relative = resolveServer({
    configured: "bin/robosim",
    extensionPath: "/ext",
    platform: "linux",
    pathVariable: "",
    isExecutableFile: () => true,
  });
  assert.equal(relative.ok, false, "a relative path would depend on the (untrusted) current folder");
});

test("server: the bundled binary comes before PATH; robosim.exe on Windows", () => {
  const linux = resolveServer({
    configured: null,
    extensionPath: "/ext",
    platform: "linux",
    pathVariable: "/usr/bin",
    isExecutableFile: files(["/ext/server/robosim", "/usr/bin/robosim"]),
  });
  assert.deepEqual(linux, { ok: true, command: "/ext/server/robosim", source: "bundled" });
  const win = resolveServer({
    configured: "",
    extensionPath: "C:\\ext",
    platform: "win32",
    pathVariable: "C:\\tools",
    isExecutableFile: files(["C:\\ext\\server\\robosim.exe"]),
  });
  assert.deepEqual(win, { ok: true, command: "C:\\ext\\server\\robosim.exe", source: "bundled" });
});

test("server: PATH last, only absolute entries, PATHEXT on Windows", () => {
  const r = resolveServer({
    extensionPath: "/ext",
    platform: "linux",
    pathVariable: ":.:bin:/usr/local/bin:/usr/bin",
    isExecutableFile: files(["./robosim", "bin/robosim", "robosim", "/usr/bin/robosim"]),
  });
  assert.deepEqual(r, { ok: true, command: "/usr/bin/robosim", source: "path" });
  assert.equal(
    searchPath("robosim", '"C:\\Program Files\\robosim";C:\\x', "win32", files(["C:\\Program Files\\robosim\\robosim.exe"]), ".EXE;.CMD"),
    "C:\\Program Files\\robosim\\robosim.exe",
  );
});

test("server: nothing found gives a message that says what to do", () => {
  const r = resolveServer({ extensionPath: "/ext", platform: "linux", pathVariable: "/usr/bin", isExecutableFile: () => false });
  assert.equal(r.ok, false);
  assert.equal(r.reason, "not-found");
  assert.match(r.message, /robosim\.server\.path/);
  assert.match(r.message, /PATH/);
});

// --- .rst detection -----------------------------------------------------------

test("rst: every fixture of editors/testdata/filetype is classified as its name says", () => {
  const rst = readdirSync(fixtures).filter((f) => f.endsWith(".rst"));
  assert.ok(rst.length >= 8, "fixtures are missing");
  for (const f of rst) {
    const text = readFileSync(join(fixtures, f), "utf8");
    assert.equal(looksLikeRoboSim(text), f.startsWith("sim-"), `${f}: ${f.startsWith("sim-") ? "RoboSim" : "reStructuredText"}`);
  }
});

test("rst: declarations and reStructuredText markup", () => {
  const yes = [
    "package sim",
    "package a::b // comment",
    "\uFEFFimport lawnmower::*",
    "stm S {",
    "stm S",
    "robotic platform P {",
    "operation op(x : nat) {",
    "  module M{ }",
    "/* header */ controller C {",
    "datatype ^state {",
    "\r\n\r\ninterface I {\r\n}\r\n",
  ];
  const no = [
    "",
    "// only a comment",
    "package management\n------------------",
    "stm machines\n\n.. note:: x",
    "interface of the robot",
    "type the command below",
    "Package sim",
    "package sim\n\n.. code-block:: robosim",
    "Title\n=====\n\nstm S {",
  ];
  for (const t of yes) assert.ok(looksLikeRoboSim(t), `RoboSim: ${JSON.stringify(t)}`);
  for (const t of no) assert.ok(!looksLikeRoboSim(t), `not RoboSim: ${JSON.stringify(t)}`);
});

test("rst: files.associations globs, longest match wins", () => {
  assert.ok(globToRegExp("*.rst").test("a.RST"));
  assert.ok(globToRegExp("**/sim/**/*.rst").test("/home/u/sim/a/b.rst"));
  assert.ok(globToRegExp("**/sim/**/*.rst").test("/home/u/sim/b.rst"));
  assert.ok(!globToRegExp("**/sim/*.rst").test("/home/u/docs/b.rst"));
  assert.ok(globToRegExp("*.{rst,txt}").test("x.txt"));
  assert.ok(globToRegExp("model[0-9].rst").test("model3.rst"));
  assert.equal(userAssociation("/w/docs/a.rst", { "*.rst": "restructuredtext" }), "restructuredtext");
  assert.equal(userAssociation("/w/sim/a.rst", { "*.rst": "restructuredtext", "**/sim/*.rst": "robosim" }), "robosim");
  assert.equal(userAssociation("C:\\w\\sim\\a.rst", { "**/sim/*.rst": "robosim" }), "robosim");
  assert.equal(userAssociation("/w/a.rst", { "*.md": "markdown" }), undefined);
  assert.equal(userAssociation("/w/a.rst", undefined), undefined);
});

test("rst: the switcher respects the setting, files.associations and a manual language change", () => {
  const robosimText = "package sim\nstm S {\n}\n";
  const doc = (over = {}) => ({
    uri: "file:///w/a.rst",
    fsPath: "/w/a.rst",
    languageId: "restructuredtext",
    text: robosimText,
    detect: true,
    associations: {},
    ...over,
  });
  const s = new RstSwitcher(1000);
  assert.equal(s.shouldSwitch(doc(), 0), true);
  assert.equal(s.shouldSwitch(doc({ languageId: "plaintext" }), 0), true);
  assert.equal(s.shouldSwitch(doc({ text: "Title\n=====\n" }), 0), false);
  assert.equal(s.shouldSwitch(doc({ detect: false }), 0), false);
  assert.equal(s.shouldSwitch(doc({ associations: { "*.rst": "restructuredtext" } }), 0), false);
  assert.equal(s.shouldSwitch(doc({ languageId: "markdown" }), 0), false);
  assert.equal(s.shouldSwitch(doc({ fsPath: "/w/a.txt", uri: "file:///w/a.txt", languageId: "plaintext" }), 0), false);
  // Our own switch: closed as reStructuredText, reopened as RoboSim.
  s.onDidClose("file:///w/a.rst", "restructuredtext", 10);
  assert.equal(s.shouldSwitch(doc({ languageId: "robosim" }), 10), false);
  // The user picks reStructuredText for it: closed as RoboSim, reopened at once.
  s.onDidClose("file:///w/a.rst", "robosim", 5000);
  assert.equal(s.shouldSwitch(doc(), 5010), false, "a manual change is kept");
  assert.equal(s.shouldSwitch(doc(), 99999), false, "…for the rest of the session");
  // A document disposed long ago and opened again is examined again.
  const t = new RstSwitcher(1000);
  t.onDidClose("file:///w/a.rst", "robosim", 0);
  assert.equal(t.shouldSwitch(doc(), 60000), true);
});
