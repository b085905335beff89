// The packaged .vsix (built by `npm run package`, which `npm test` runs
// first): it holds the bundled code, the four grammars (identical to
// ../../syntax), the language configuration and a manifest whose
// contributions match them.
import assert from "node:assert/strict";
import { existsSync, readFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { builtinModules } from "node:module";
import { test } from "node:test";
import { fileURLToPath } from "node:url";
import { readZip } from "../scripts/zip.mjs";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const syntaxDir = join(root, "..", "..", "syntax");
const pkg = JSON.parse(readFileSync(join(root, "package.json"), "utf8"));
const vsixPath = join(root, "dist", `${pkg.name}-${pkg.version}.vsix`);

const LANGUAGES = {
  robochart: { ext: ".rct", scope: "source.robochart", grammar: "robochart.tmLanguage.json" },
  robosim: { ext: ".rst", scope: "source.robosim", grammar: "robosim.tmLanguage.json" },
  "robochart-assertions": {
    ext: ".assertions",
    scope: "source.robochart.assertions",
    grammar: "robochart-assertions.tmLanguage.json",
  },
  "robosim-assertions": { ext: ".rsa", scope: "source.robosim.assertions", grammar: "robosim-assertions.tmLanguage.json" },
};

function load() {
  assert.ok(existsSync(vsixPath), `${vsixPath} is missing: run \`npm run package\` first`);
  const zip = readZip(vsixPath);
  const read = (name) => {
    const entry = zip.get(name);
    assert.ok(entry, `${name} is not in the .vsix`);
    return entry();
  };
  return { zip, read, manifest: JSON.parse(read("extension/package.json").toString("utf8")) };
}

test("the .vsix holds the code, the grammars and the language configuration, and nothing else", () => {
  const { zip } = load();
  const names = [...zip.keys()].sort();
  const expected = [
    "[Content_Types].xml",
    "extension.vsixmanifest",
    "extension/language-configuration.json",
    "extension/out/extension.js",
    "extension/package.json",
    "extension/readme.md",
    ...Object.values(LANGUAGES).map((l) => `extension/syntaxes/${l.grammar}`),
  ];
  for (const name of expected) assert.ok(names.includes(name), `${name} is not in the .vsix (it has ${names.join(", ")})`);
  const allowed = new Set([...expected, "extension/changelog.md", "extension/server/robosim", "extension/server/robosim.exe"]);
  const extra = names.filter((n) => !allowed.has(n));
  assert.deepEqual(extra, [], "unexpected files in the .vsix (node_modules, sources, tests?)");
});

test("the packaged grammars are byte-identical to syntax/*.tmLanguage.json", () => {
  const { read } = load();
  for (const { grammar, scope } of Object.values(LANGUAGES)) {
    const packed = read(`extension/syntaxes/${grammar}`);
    assert.ok(packed.equals(readFileSync(join(syntaxDir, grammar))), `${grammar} differs from syntax/${grammar}`);
    assert.equal(JSON.parse(packed.toString("utf8")).scopeName, scope);
  }
});

test("package.json contributes the four languages with their grammars and configuration", () => {
  const { manifest, read } = load();
  const langs = manifest.contributes.languages;
  assert.deepEqual(langs.map((l) => l.id).sort(), Object.keys(LANGUAGES).sort());
  for (const l of langs) {
    assert.equal(l.configuration, "./language-configuration.json", `${l.id}: language configuration`);
    if (l.id === "robosim") {
      // `.rst` belongs to reStructuredText: no static claim (it would win
      // over the built-in language for every .rst file); the extension
      // switches RoboSim-looking files at run time instead.
      assert.equal(l.extensions, undefined, "robosim must not claim .rst statically");
      const firstLine = new RegExp(l.firstLine);
      for (const yes of ["stm Mower {", "module M {", "import lawnmower::*", "robotic platform P {", "controller C{"]) {
        assert.ok(firstLine.test(yes), `firstLine should match ${JSON.stringify(yes)}`);
      }
      for (const no of ["package main", "import os", "interface Foo {", "Title", ".. note::", "// comment", "function f() {"]) {
        assert.ok(!firstLine.test(no), `firstLine should not match ${JSON.stringify(no)}`);
      }
    } else {
      assert.deepEqual(l.extensions, [LANGUAGES[l.id].ext], `${l.id}: extensions`);
    }
  }
  const grammars = manifest.contributes.grammars;
  assert.equal(grammars.length, 4);
  for (const g of grammars) {
    const want = LANGUAGES[g.language];
    assert.ok(want, `grammar for unknown language ${g.language}`);
    assert.equal(g.scopeName, want.scope);
    assert.equal(g.path, `./syntaxes/${want.grammar}`);
    read(`extension/${g.path.slice(2)}`);
  }
  assert.equal(manifest.main, "./out/extension.js");
  read("extension/out/extension.js");
});

test("the language configuration has the comments, brackets, pairs, folding and indentation rules", () => {
  const { read } = load();
  const conf = JSON.parse(read("extension/language-configuration.json").toString("utf8"));
  assert.deepEqual(conf.comments, { lineComment: "//", blockComment: ["/*", "*/"] });
  const brackets = conf.brackets.map((b) => b.join(" "));
  for (const b of ["{ }", "[ ]", "( )", "(| |)", "[| |]"]) assert.ok(brackets.includes(b), `bracket pair ${b}`);
  const closing = conf.autoClosingPairs.map((p) => p.open + p.close);
  for (const p of ["{}", "[]", "()", '""', "''"]) assert.ok(closing.includes(p), `auto-closing pair ${p}`);
  const start = new RegExp(conf.folding.markers.start);
  const end = new RegExp(conf.folding.markers.end);
  assert.ok(start.test("  // region motors") && end.test("  // endregion"));
  assert.ok(start.test("csp-begin") && end.test("csp-end"));
  const inc = new RegExp(conf.indentationRules.increaseIndentPattern);
  const dec = new RegExp(conf.indentationRules.decreaseIndentPattern);
  assert.ok(inc.test("stm S {") && inc.test("\ttransition t {") && !inc.test("state S { }") && !inc.test("// {"));
  assert.ok(dec.test("}") && dec.test("\t}") && dec.test("  |)") && !dec.test("x = 1"));
  assert.ok(new RegExp(`^(?:${conf.wordPattern})$`).test("^state"));
});

test("settings, commands and restricted-mode declarations", () => {
  const { manifest } = load();
  const props = manifest.contributes.configuration.properties;
  const serverPath = props["robosim.server.path"];
  assert.equal(serverPath.scope, "machine", "a workspace must not be able to choose the executable");
  assert.deepEqual(props["robosim.rules"].enum, ["paper", "robotool"]);
  assert.equal(props["robosim.rules"].default, "paper");
  assert.deepEqual(props["robosim.trace.server"].enum, ["off", "messages", "verbose"]);
  assert.equal(props["robosim.rst.detect"].type, "boolean");
  assert.deepEqual(props["robosim.verify.semantics"].enum, ["robotool3", "paper2019"]);
  assert.equal(props["robosim.verify.semantics"].default, "robotool3");
  assert.equal(props["robosim.verify.timeoutSeconds"].type, "number");
  assert.equal(props["robosim.verify.timeoutSeconds"].default, 60);
  const buffer = new RegExp(props["robosim.verify.asyncBuffer"].pattern);
  for (const ok of ["", "none", "1", "1:overwrite", "8:block"]) assert.ok(buffer.test(ok), ok);
  for (const bad of ["0", "9", "1:drop", "x"]) assert.ok(!buffer.test(bad), bad);
  const commands = manifest.contributes.commands.map((c) => c.command).sort();
  assert.deepEqual(commands, ["robosim.restartServer", "robosim.showDiagram", "robosim.showOutput"]);
  const untrusted = manifest.capabilities.untrustedWorkspaces;
  assert.equal(untrusted.supported, "limited");
  assert.ok(untrusted.description.length > 0);
  assert.deepEqual(untrusted.restrictedConfigurations, ["robosim.server.path"]);
  assert.match(manifest.engines.vscode, /^\^1\.82\./, "engines.vscode must match vscode-languageclient 9");
  assert.equal(manifest.dependencies["vscode-languageclient"], "9.0.1");
  for (const event of ["onLanguage:restructuredtext", "onLanguage:plaintext"]) {
    assert.ok(manifest.activationEvents.includes(event), `activation event ${event} (for .rst detection)`);
  }
});

test("the bundle loads the language client and leaves only `vscode` external", () => {
  const { read } = load();
  const code = read("extension/out/extension.js").toString("utf8");
  const requires = [...code.matchAll(/require\(["']([^"']+)["']\)/g)].map((m) => m[1]);
  const nonBuiltin = requires.filter((r) => !r.startsWith("node:") && !builtinModules.includes(r));
  assert.deepEqual([...new Set(nonBuiltin)], ["vscode"]);
});
