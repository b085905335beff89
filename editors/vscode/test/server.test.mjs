// End to end: the real `robosim lsp` binary, driven over stdio by
// vscode-languageserver-protocol, the library VS Code's language client is
// built on. ROBOSIM_BIN names the binary (default ../../target/debug/robosim,
// relative to editors/vscode).
import assert from "node:assert/strict";
import { spawn } from "node:child_process";
import { cpSync, existsSync, mkdtempSync, readFileSync, rmSync } from "node:fs";
import { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { after, before, describe, it } from "node:test";
import { fileURLToPath, pathToFileURL } from "node:url";

const require = createRequire(import.meta.url);
const {
  createProtocolConnection,
  StreamMessageReader,
  StreamMessageWriter,
  InitializeRequest,
  InitializedNotification,
  ShutdownRequest,
  ExitNotification,
  DidOpenTextDocumentNotification,
  DidChangeTextDocumentNotification,
  DidChangeConfigurationNotification,
  PublishDiagnosticsNotification,
  ConfigurationRequest,
  DocumentSymbolRequest,
  HoverRequest,
  DefinitionRequest,
  DocumentFormattingRequest,
  FoldingRangeRequest,
  SemanticTokensRequest,
  CodeLensRequest,
  ExecuteCommandRequest,
  DiagnosticSeverity,
} = require("vscode-languageserver-protocol/node");

const here = dirname(fileURLToPath(import.meta.url));
const extensionRoot = join(here, "..");
const bin = resolve(extensionRoot, process.env.ROBOSIM_BIN ?? "../../target/debug/robosim");
const fixtures = join(extensionRoot, "..", "testdata", "lsp");
const TIMEOUT = 20000; // a debug build, on a 2-core machine

function withTimeout(promise, ms, what) {
  let timer;
  return Promise.race([
    promise,
    new Promise((_, reject) => {
      timer = setTimeout(() => reject(new Error(`timed out after ${ms} ms waiting for ${what}`)), ms);
    }),
  ]).finally(() => clearTimeout(timer));
}

describe("robosim lsp over stdio", { timeout: 120000 }, () => {
  let child;
  let conn;
  let workspace;
  let stderr = "";
  let exitCode; // set when the process ends
  let exited;
  let initResult;
  const published = new Map(); // uri → list of publishDiagnostics params, in arrival order
  const listeners = new Set();
  const configurationRequests = [];
  const logs = [];

  const uriOf = (name) => pathToFileURL(join(workspace, name)).href;
  const textOf = (name) => readFileSync(join(workspace, name), "utf8");

  /** Resolves with the first publish for `uri` (index ≥ `from`) satisfying `pred`. */
  function waitForDiagnostics(uri, pred, from = 0) {
    const find = () => (published.get(uri) ?? []).slice(from).find(pred);
    const found = find();
    if (found) return Promise.resolve(found);
    const p = new Promise((resolve) => {
      const check = () => {
        const hit = find();
        if (hit) {
          listeners.delete(check);
          resolve(hit);
        }
      };
      listeners.add(check);
    });
    return withTimeout(p, TIMEOUT, `publishDiagnostics for ${uri}; got ${JSON.stringify(published.get(uri) ?? [])}`);
  }

  function open(name, languageId) {
    const before = (published.get(uriOf(name)) ?? []).length;
    conn.sendNotification(DidOpenTextDocumentNotification.type, {
      textDocument: { uri: uriOf(name), languageId, version: 1, text: textOf(name) },
    });
    return before;
  }

  before(async () => {
    assert.ok(
      existsSync(bin),
      `the server binary ${bin} does not exist: build it with \`cargo build -p robosim-cli\` or set ROBOSIM_BIN`,
    );
    workspace = mkdtempSync(join(tmpdir(), "robosim-lsp-test-"));
    cpSync(fixtures, workspace, { recursive: true });

    child = spawn(bin, ["lsp"], { cwd: workspace, stdio: ["pipe", "pipe", "pipe"] });
    child.stderr.on("data", (d) => {
      stderr += d.toString();
    });
    exited = new Promise((resolve) => {
      child.on("exit", (code, signal) => {
        exitCode = code ?? signal;
        resolve(exitCode);
      });
    });
    child.on("error", (e) => {
      stderr += `spawn error: ${e.message}\n`;
    });

    conn = createProtocolConnection(new StreamMessageReader(child.stdout), new StreamMessageWriter(child.stdin));
    conn.onNotification(PublishDiagnosticsNotification.type, (params) => {
      const list = published.get(params.uri) ?? [];
      list.push(params);
      published.set(params.uri, list);
      for (const l of [...listeners]) l();
    });
    conn.onRequest(ConfigurationRequest.type, (params) => {
      configurationRequests.push(params);
      return params.items.map((item) => (item.section === "robosim" ? { rules: "paper" } : null));
    });
    conn.onNotification("window/logMessage", (p) => logs.push(p.message));
    conn.onNotification("window/showMessage", (p) => logs.push(p.message));
    conn.onRequest("window/workDoneProgress/create", () => null);
    conn.onRequest("client/registerCapability", () => null);
    conn.onUnhandledNotification(() => {});
    conn.listen();

    initResult = await withTimeout(
      conn.sendRequest(InitializeRequest.type, {
        processId: process.pid,
        clientInfo: { name: "robosim-editors-test", version: "1" },
        rootUri: pathToFileURL(workspace).href,
        workspaceFolders: [{ uri: pathToFileURL(workspace).href, name: "ws" }],
        initializationOptions: { rules: "paper" },
        capabilities: {
          general: { positionEncodings: ["utf-16"] },
          // As the extension declares: it runs robosim.showDiagram itself.
          experimental: { commands: { commands: ["robosim.showDiagram"] } },
          workspace: { configuration: true, workspaceFolders: true, didChangeConfiguration: { dynamicRegistration: false } },
          textDocument: {
            synchronization: { dynamicRegistration: false },
            publishDiagnostics: { relatedInformation: true, versionSupport: true, codeDescriptionSupport: true },
            documentSymbol: { hierarchicalDocumentSymbolSupport: true },
            hover: { contentFormat: ["markdown", "plaintext"] },
            definition: { linkSupport: false },
            foldingRange: { lineFoldingOnly: true },
          },
        },
      }),
      TIMEOUT,
      "the initialize response",
    );
    conn.sendNotification(InitializedNotification.type, {});
  });

  after(async () => {
    if (exitCode === undefined && child) child.kill();
    conn?.dispose();
    if (workspace) rmSync(workspace, { recursive: true, force: true });
    if (process.env.ROBOSIM_TEST_VERBOSE) {
      console.log(`server stderr:\n${stderr}\nlog messages:\n${logs.join("\n")}`);
    }
  });

  it("initializes with incremental sync, symbols and the server's name", () => {
    const caps = initResult.capabilities;
    assert.ok(caps.textDocumentSync, "textDocumentSync");
    assert.ok(caps.documentSymbolProvider, "documentSymbolProvider");
    if (caps.positionEncoding !== undefined) assert.equal(caps.positionEncoding, "utf-16");
  });

  it("reads the `robosim` section through workspace/configuration", async () => {
    const asked = new Promise((resolve) => {
      const poll = setInterval(() => {
        if (configurationRequests.length > 0) {
          clearInterval(poll);
          resolve();
        }
      }, 20);
    });
    await withTimeout(asked, TIMEOUT, "a workspace/configuration request");
    const sections = configurationRequests.flatMap((r) => r.items.map((i) => i.section));
    assert.ok(sections.includes("robosim"), `sections asked: ${JSON.stringify(sections)}`);
  });

  it("publishes SYN-01 with its range for a broken .rct document", async () => {
    const from = open("broken.rct", "robochart");
    const p = await waitForDiagnostics(uriOf("broken.rct"), (p) => p.diagnostics.length > 0, from);
    const syn = p.diagnostics.filter((d) => d.code === "SYN-01");
    assert.equal(syn.length, 1, `diagnostics: ${JSON.stringify(p.diagnostics)}`);
    assert.deepEqual(syn[0].range, { start: { line: 4, character: 22 }, end: { line: 4, character: 23 } });
    assert.equal(syn[0].severity, DiagnosticSeverity.Error);
    assert.match(syn[0].message, /`;`/);
    assert.equal(p.diagnostics.length, 1, `only the syntax error: ${JSON.stringify(p.diagnostics)}`);
  });

  it("clears the diagnostics after an incremental edit fixes the document", async () => {
    const uri = uriOf("broken.rct");
    const from = (published.get(uri) ?? []).length;
    conn.sendNotification(DidChangeTextDocumentNotification.type, {
      textDocument: { uri, version: 2 },
      contentChanges: [{ range: { start: { line: 4, character: 22 }, end: { line: 4, character: 23 } }, text: "" }],
    });
    const p = await waitForDiagnostics(uri, (p) => p.diagnostics.length === 0, from);
    if (p.version !== undefined && p.version !== null) assert.equal(p.version, 2);
  });

  it("publishes no diagnostic for a well-formed RoboSim document", async () => {
    const uri = uriOf("counter.rst");
    const from = open("counter.rst", "robosim");
    const p = await waitForDiagnostics(uri, () => true, from);
    assert.deepEqual(p.diagnostics, []);
  });

  it("lists the document's symbols", async () => {
    const symbols = await withTimeout(
      conn.sendRequest(DocumentSymbolRequest.type, { textDocument: { uri: uriOf("counter.rst") } }),
      TIMEOUT,
      "documentSymbol",
    );
    assert.ok(Array.isArray(symbols) && symbols.length > 0, `symbols: ${JSON.stringify(symbols)}`);
    const names = [];
    const walk = (list) => {
      for (const s of list) {
        names.push(s.name);
        if (s.children) walk(s.children);
      }
    };
    walk(symbols);
    for (const name of ["Ticks", "tick", "Counter", "count", "Counting", "t1"]) {
      assert.ok(names.includes(name), `symbol ${name} missing from ${JSON.stringify(names)}`);
    }
    const counter = symbols.find((s) => s.name === "Counter");
    if (counter && "children" in counter) {
      assert.ok(
        counter.children.some((c) => c.name === "Counting"),
        "the state Counting is a child of the machine Counter",
      );
    }
  });

  it("hovers on a name", async () => {
    assert.ok(initResult.capabilities.hoverProvider, "the server advertises hoverProvider");
    // `uses Ticks` in counter.rst: line 10, the `T` of `Ticks` at character 22.
    const line = textOf("counter.rst").split("\n")[10];
    const character = line.indexOf("Ticks") + 2;
    assert.ok(character >= 2, `fixture line 10 is ${JSON.stringify(line)}`);
    const hover = await withTimeout(
      conn.sendRequest(HoverRequest.type, { textDocument: { uri: uriOf("counter.rst") }, position: { line: 10, character } }),
      TIMEOUT,
      "hover",
    );
    assert.ok(hover, "a hover result");
    const text = JSON.stringify(hover.contents);
    assert.match(text, /Ticks/, `hover contents: ${text}`);
  });

  it("goes to the definition of a name", async () => {
    assert.ok(initResult.capabilities.definitionProvider, "the server advertises definitionProvider");
    const line = textOf("counter.rst").split("\n")[10];
    const character = line.indexOf("Ticks") + 1;
    const result = await withTimeout(
      conn.sendRequest(DefinitionRequest.type, { textDocument: { uri: uriOf("counter.rst") }, position: { line: 10, character } }),
      TIMEOUT,
      "definition",
    );
    const locations = Array.isArray(result) ? result : [result];
    assert.ok(locations.length > 0 && locations[0], `definition: ${JSON.stringify(result)}`);
    const loc = locations[0];
    assert.equal(loc.uri ?? loc.targetUri, uriOf("counter.rst"));
    assert.equal((loc.range ?? loc.targetSelectionRange).start.line, 3, "interface Ticks is declared on line 3");
  });

  it("answers folding, semantic-token and formatting requests", async () => {
    const caps = initResult.capabilities;
    const textDocument = { uri: uriOf("counter.rst") };
    assert.ok(caps.foldingRangeProvider, "the server advertises foldingRangeProvider");
    const ranges = await conn.sendRequest(FoldingRangeRequest.type, { textDocument });
    assert.ok(Array.isArray(ranges) && ranges.some((r) => r.startLine === 7), `folding: ${JSON.stringify(ranges)}`);
    assert.ok(caps.semanticTokensProvider, "the server advertises semanticTokensProvider");
    const tokens = await conn.sendRequest(SemanticTokensRequest.type, { textDocument });
    assert.ok(tokens && tokens.data.length > 0 && tokens.data.length % 5 === 0, "semantic tokens");
    assert.ok(caps.documentFormattingProvider, "the server advertises documentFormattingProvider");
    const edits = await conn.sendRequest(DocumentFormattingRequest.type, {
      textDocument,
      options: { tabSize: 4, insertSpaces: true },
    });
    assert.ok(edits === null || Array.isArray(edits), "formatting edits");
  });

  it("offers verification lenses whose command runs through workspace/executeCommand", async () => {
    // vscode-languageclient registers every command of
    // `executeCommandProvider` and sends `workspace/executeCommand` with the
    // lens's arguments as they are: nothing to register in the extension.
    assert.deepEqual(initResult.capabilities.executeCommandProvider?.commands, ["robosim.verify"]);
    assert.ok(initResult.capabilities.codeLensProvider, "the server advertises codeLensProvider");
    const gt3 = join(extensionRoot, "..", "..", "tests", "data", "verify", "gt3");
    const uri = (name) => pathToFileURL(join(workspace, "gt3", name)).href;
    for (const [name, languageId] of [
      ["design.rct", "robochart"],
      ["checks.rsa", "robosim-assertions"],
    ]) {
      conn.sendNotification(DidOpenTextDocumentNotification.type, {
        textDocument: { uri: uri(name), languageId, version: 1, text: readFileSync(join(gt3, name), "utf8") },
      });
    }
    const lenses = await withTimeout(
      conn.sendRequest(CodeLensRequest.type, { textDocument: { uri: uri("checks.rsa") } }),
      TIMEOUT,
      "codeLens",
    );
    const s1 = lenses.find((l) => l.command?.arguments?.[1] === "S1");
    assert.ok(s1, `lenses: ${JSON.stringify(lenses)}`);
    assert.equal(s1.command.command, "robosim.verify");
    assert.equal(s1.command.title, "▶ Verify");
    const from = (published.get(uri("checks.rsa")) ?? []).length;
    const result = await withTimeout(
      conn.sendRequest(ExecuteCommandRequest.type, { command: s1.command.command, arguments: s1.command.arguments }),
      TIMEOUT,
      "executeCommand",
    );
    assert.equal(result, null);
    const p = await waitForDiagnostics(
      uri("checks.rsa"),
      (p) => p.diagnostics.some((d) => d.code === "RS-VERIFY"),
      from,
    );
    const d = p.diagnostics.find((d) => d.code === "RS-VERIFY");
    assert.equal(d.severity, DiagnosticSeverity.Error);
    assert.equal(d.message, "CFootBot cannot be scheduled in cycles of period 1");
    assert.ok(d.relatedInformation.length > 0 && d.relatedInformation.every((r) => r.location.uri === uri("design.rct")));
    const after = await conn.sendRequest(CodeLensRequest.type, { textDocument: { uri: uri("checks.rsa") } });
    assert.equal(after.find((l) => l.command?.arguments?.[1] === "S1").command.title, "✘ fail — re-run");
  });

  it("offers diagram lenses whose command the extension runs with robosim/diagram", async () => {
    // Not the server's command: vscode-languageclient must not register it.
    assert.ok(!initResult.capabilities.executeCommandProvider.commands.includes("robosim.showDiagram"));
    const uri = pathToFileURL(join(workspace, "gt3", "design.rct")).href;
    const lenses = await withTimeout(
      conn.sendRequest(CodeLensRequest.type, { textDocument: { uri } }),
      TIMEOUT,
      "codeLens",
    );
    const shows = lenses.filter((l) => l.command?.command === "robosim.showDiagram");
    assert.deepEqual(
      shows.map((l) => [l.command.title, ...l.command.arguments]),
      [
        ["◇ Show diagram", uri, "paper_design::SMovement"],
        ["◇ Show diagram", uri, "paper_design::Movement"],
        ["◇ Show diagram", uri, "paper_design::CFootBot"],
      ],
    );
    // What the extension's command sends (design.rct of GT-3 is open: the
    // test above opened it).
    const [target, element] = shows[0].command.arguments;
    const result = await withTimeout(
      conn.sendRequest("robosim/diagram", { textDocument: { uri: target }, element }),
      TIMEOUT,
      "robosim/diagram",
    );
    assert.equal(result.diagrams.length, 1);
    assert.equal(result.diagrams[0].model.qualifiedName, "paper_design::SMovement");
    assert.deepEqual(
      result.diagrams[0].model.region.nodes.map((n) => n.name),
      ["i0", "Moving", "Turning"],
    );
    assert.match(result.diagrams[0].svg, /^<svg [^>]*class="robosim-diagram"/);
    assert.match(result.diagrams[0].svg, /data-id="Moving"[^>]* data-line="\d+" data-character="\d+"/);
    await assert.rejects(
      conn.sendRequest("robosim/diagram", { textDocument: { uri }, element: "Nowhere" }),
      (e) => e.code === -32602 && /Nowhere/.test(e.message),
    );
  });

  it("accepts a configuration change and keeps serving", async () => {
    conn.sendNotification(DidChangeConfigurationNotification.type, { settings: { robosim: { rules: "robotool" } } });
    const symbols = await withTimeout(
      conn.sendRequest(DocumentSymbolRequest.type, { textDocument: { uri: uriOf("counter.rst") } }),
      TIMEOUT,
      "documentSymbol after a configuration change",
    );
    assert.ok(Array.isArray(symbols) && symbols.length > 0);
  });

  it("shuts down and exits with status 0", async () => {
    await withTimeout(conn.sendRequest(ShutdownRequest.type), TIMEOUT, "the shutdown response");
    await conn.sendNotification(ExitNotification.type);
    const code = await withTimeout(exited, TIMEOUT, "the server to exit");
    assert.equal(code, 0, `exit status; stderr:\n${stderr}`);
  });
});
