// Loads the bundled extension (out/extension.js) against a stand-in for the
// `vscode` module and checks what activate() does without starting a
// server: the commands it registers, the `.rst` switch, and the error shown
// when no server binary is found. The real editor is not needed.
import assert from "node:assert/strict";
import { mkdtempSync, rmSync } from "node:fs";
import Module, { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { dirname, join } from "node:path";
import { after, before, test } from "node:test";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const require = createRequire(import.meta.url);

/** Something that can be called, constructed and indexed to any depth. */
function anything() {
  const f = function () {};
  return new Proxy(f, {
    get: (target, prop) => {
      if (prop === Symbol.toPrimitive) return () => "";
      if (prop === "then") return undefined; // not a thenable
      if (!(prop in target)) target[prop] = anything();
      return target[prop];
    },
    apply: () => anything(),
    construct: () => anything(),
  });
}

function makeVscode(state) {
  const emitter = (list) => (listener) => {
    list.push(listener);
    return { dispose() {} };
  };
  const config = (section) => ({
    get: (key, dflt) => {
      const v = state.settings[`${section}.${key}`];
      return v === undefined ? dflt : v;
    },
  });
  const vscode = {
    workspace: {
      textDocuments: state.openDocuments,
      getConfiguration: (section) => config(section),
      onDidOpenTextDocument: emitter(state.onOpen),
      onDidCloseTextDocument: emitter(state.onClose),
      onDidChangeConfiguration: emitter(state.onConfig),
      onDidChangeTextDocument: emitter([]),
    },
    window: {
      createOutputChannel: (name) => ({
        name,
        lines: state.output,
        appendLine: (l) => state.output.push(l),
        append: (l) => state.output.push(l),
        show: () => state.shown.push(name),
        dispose() {},
      }),
      showErrorMessage: (message, ...items) => {
        state.errors.push({ message, items });
        return Promise.resolve(state.errorChoice);
      },
      showInformationMessage: (message, ...items) => {
        state.infos.push({ message, items });
        return Promise.resolve(undefined);
      },
    },
    commands: {
      registerCommand: (id, fn) => {
        state.commands.set(id, fn);
        return { dispose() {} };
      },
      executeCommand: (...args) => {
        state.executed.push(args);
        return Promise.resolve();
      },
    },
    languages: {
      onDidChangeDiagnostics: () => ({ dispose() {} }),
      setTextDocumentLanguage: (doc, language) => {
        state.switched.push({ path: doc.uri.fsPath, language });
        return Promise.resolve(doc);
      },
    },
  };
  return new Proxy(vscode, {
    get: (target, prop) => (prop in target ? target[prop] : anything()),
  });
}

function doc(fsPath, languageId, text) {
  return {
    uri: { scheme: "file", fsPath, toString: () => `file://${fsPath}` },
    languageId,
    getText: () => text,
  };
}

const state = {
  settings: {},
  openDocuments: [],
  onOpen: [],
  onClose: [],
  onConfig: [],
  output: [],
  shown: [],
  errors: [],
  infos: [],
  commands: new Map(),
  executed: [],
  switched: [],
  errorChoice: undefined,
};
let extension;
let emptyPath;
const savedPath = process.env.PATH;
const originalLoad = Module._load;

before(() => {
  const fake = makeVscode(state);
  Module._load = function (request, ...rest) {
    if (request === "vscode") return fake;
    return originalLoad.call(this, request, ...rest);
  };
  // No `robosim` on PATH, whatever the machine has.
  emptyPath = mkdtempSync(join(tmpdir(), "robosim-empty-path-"));
  process.env.PATH = emptyPath;
  extension = require(join(root, "out", "extension.js"));
  extension.activate({ extensionPath: join(emptyPath, "no-extension"), subscriptions: [] });
});

after(() => {
  Module._load = originalLoad;
  process.env.PATH = savedPath;
  rmSync(emptyPath, { recursive: true, force: true });
});

const flush = () => new Promise((r) => setTimeout(r, 20));

test("activate() registers the three commands and starts nothing while no model is open", () => {
  assert.deepEqual([...state.commands.keys()].sort(), ["robosim.restartServer", "robosim.showDiagram", "robosim.showOutput"]);
  assert.equal(state.errors.length, 0);
  assert.equal(state.onOpen.length, 1);
  state.commands.get("robosim.showOutput")();
  assert.deepEqual(state.shown, ["RoboSim Language Server"]);
});

test("a .rst file that looks like RoboSim is switched to robosim; reStructuredText is not", async () => {
  state.onOpen[0](doc("/w/docs/index.rst", "restructuredtext", "Title\n=====\n\nText.\n"));
  state.onOpen[0](doc("/w/sim/model.rst", "restructuredtext", "// header\npackage sim\nstm S {\n}\n"));
  state.settings["files.associations"] = { "**/forced/*.rst": "restructuredtext" };
  state.onOpen[0](doc("/w/forced/model.rst", "restructuredtext", "package sim\n"));
  delete state.settings["files.associations"];
  await flush();
  assert.deepEqual(state.switched, [{ path: "/w/sim/model.rst", language: "robosim" }]);
});

test("a missing server gives an error with a button that opens the setting", async () => {
  state.settings["robosim.server.path"] = "/nonexistent/robosim";
  state.errorChoice = "Open Settings";
  state.onOpen[0](doc("/w/a.rct", "robochart", "stm S {}\n"));
  await flush();
  assert.equal(state.errors.length, 1);
  assert.match(state.errors[0].message, /robosim\.server\.path is set to "\/nonexistent\/robosim"/);
  assert.deepEqual(state.errors[0].items, ["Open Settings", "Show Output"]);
  assert.deepEqual(state.executed, [["workbench.action.openSettings", "robosim.server.path"]]);
  // Other documents do not repeat the error…
  state.onOpen[0](doc("/w/b.rct", "robochart", "stm T {}\n"));
  await flush();
  assert.equal(state.errors.length, 1);
  // …but the restart command tries again.
  delete state.settings["robosim.server.path"];
  state.errorChoice = undefined;
  await state.commands.get("robosim.restartServer")();
  assert.equal(state.errors.length, 2);
  assert.match(state.errors[1].message, /was not found/);
  assert.ok(state.output.some((l) => l.includes("was not found")), "the error is also in the output channel");
});
