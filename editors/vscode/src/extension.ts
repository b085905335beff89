// The VS Code client of the robosim language server (`robosim lsp`).

import * as fs from "fs";
import * as path from "path";
import * as vscode from "vscode";
import {
  LanguageClient,
  LanguageClientOptions,
  RevealOutputChannelOn,
  ServerOptions,
} from "vscode-languageclient/node";
import { DIAGRAM_REQUEST, DiagramResult, DiagramViews, SHOW_DIAGRAM } from "./diagram";
import { RstSwitcher } from "./rst-detect";
import { binaryName, resolveServer } from "./server-path";

/** The languages the server handles; also its `languageId`s. */
export const LANGUAGES = ["robochart", "robosim", "robochart-assertions", "robosim-assertions"] as const;

const CLIENT_ID = "robosim"; // also the prefix of `robosim.trace.server`
const CLIENT_NAME = "RoboSim Language Server";

let client: LanguageClient | undefined;
let starting: Promise<void> | undefined;
// Set when the server could not be found or started; documents that open
// later do not retry (and repeat the error) until the restart command or a
// change of robosim.server.path.
let gaveUp = false;
let output: vscode.OutputChannel;
let traceOutput: vscode.OutputChannel;
let extensionPath = "";

function isOurs(doc: vscode.TextDocument): boolean {
  return (LANGUAGES as readonly string[]).includes(doc.languageId);
}

function log(message: string): void {
  output.appendLine(`[${new Date().toISOString()}] ${message}`);
}

async function reportMissingServer(message: string): Promise<void> {
  log(message);
  const openSettings = "Open Settings";
  const showOutput = "Show Output";
  const choice = await vscode.window.showErrorMessage(message, openSettings, showOutput);
  if (choice === openSettings) {
    await vscode.commands.executeCommand("workbench.action.openSettings", "robosim.server.path");
  } else if (choice === showOutput) {
    output.show(true);
  }
}

/** A bundled server that lost its executable bit in the .vsix gets it back. */
function ensureBundledExecutable(): void {
  if (process.platform === "win32") return;
  const bundled = path.join(extensionPath, "server", binaryName());
  try {
    const st = fs.statSync(bundled);
    if (st.isFile() && (st.mode & 0o111) === 0) fs.chmodSync(bundled, st.mode | 0o755);
  } catch {
    // No bundled server.
  }
}

async function startClient(): Promise<void> {
  ensureBundledExecutable();
  const configured = vscode.workspace.getConfiguration("robosim").get<string | null>("server.path");
  const found = resolveServer({ configured, extensionPath });
  if (!found.ok) {
    gaveUp = true;
    void reportMissingServer(found.message); // not awaited: the message stays up until dismissed
    return;
  }
  log(`starting ${found.command} lsp (found via ${found.source === "path" ? "PATH" : found.source})`);

  const serverOptions: ServerOptions = {
    // No `transport`: with `TransportKind.stdio` the client appends
    // `--stdio`; stdio is the default for an executable anyway.
    run: { command: found.command, args: ["lsp"] },
    debug: {
      command: found.command,
      args: ["lsp"],
      options: { env: { ...process.env, RUST_BACKTRACE: "1" } },
    },
  };
  const selector = LANGUAGES.flatMap((language) => [
    { scheme: "file", language },
    { scheme: "untitled", language },
  ]);
  const clientOptions: LanguageClientOptions = {
    documentSelector: selector,
    outputChannel: output,
    traceOutputChannel: traceOutput,
    revealOutputChannelOn: RevealOutputChannelOn.Never,
    // The server also reads the section itself through
    // `workspace/configuration` (section `robosim`); this sends
    // `workspace/didChangeConfiguration` when it changes.
    synchronize: { configurationSection: "robosim" },
    initializationOptions: {
      rules: vscode.workspace.getConfiguration("robosim").get<string>("rules", "paper"),
      verify: {
        semantics: vscode.workspace.getConfiguration("robosim").get<string>("verify.semantics", "robotool3"),
        timeoutSeconds: vscode.workspace.getConfiguration("robosim").get<number>("verify.timeoutSeconds", 60),
      },
    },
  };
  const c = new LanguageClient(CLIENT_ID, CLIENT_NAME, serverOptions, clientOptions);
  // The "◇ Show diagram" lenses run robosim.showDiagram, a command of this
  // extension: the server gives them to clients that say they run it
  // (rust-analyzer's `experimental.commands` convention).
  c.registerFeature({
    fillClientCapabilities(capabilities) {
      capabilities.experimental = { ...(capabilities.experimental ?? {}), commands: { commands: [SHOW_DIAGRAM] } };
    },
    initialize() {},
    getState: () => ({ kind: "static" }),
    clear() {},
  });
  client = c;
  try {
    await c.start();
    log("language server started");
  } catch (e) {
    client = undefined;
    gaveUp = true;
    const message = `The RoboSim language server (${found.command}) could not start: ${e instanceof Error ? e.message : String(e)}`;
    log(message);
    void vscode.window.showErrorMessage(message, "Show Output").then((choice) => {
      if (choice) output.show(true);
    });
  }
}

/** `robosim/diagram`, once the server runs. */
async function requestDiagrams(uri: string, element: string | undefined): Promise<DiagramResult> {
  await ensureStarted();
  const c = client;
  if (!c) throw new Error("the RoboSim language server is not running");
  const params = element === undefined ? { textDocument: { uri } } : { textDocument: { uri }, element };
  return c.sendRequest<DiagramResult>(DIAGRAM_REQUEST, params);
}

/** Starts the client once, when the first RoboChart/RoboSim document is open. */
function ensureStarted(): Promise<void> {
  if (client || gaveUp) return Promise.resolve();
  if (!starting) {
    starting = startClient().finally(() => {
      starting = undefined;
    });
  }
  return starting;
}

async function stopClient(): Promise<void> {
  const c = client;
  client = undefined;
  if (c) {
    try {
      await c.stop(2000);
    } catch (e) {
      log(`stopping the server: ${e instanceof Error ? e.message : String(e)}`);
    }
  }
}

async function restart(): Promise<void> {
  if (starting) await starting;
  await stopClient();
  gaveUp = false;
  await ensureStarted();
}

export function activate(context: vscode.ExtensionContext): void {
  extensionPath = context.extensionPath;
  output = vscode.window.createOutputChannel(CLIENT_NAME);
  traceOutput = vscode.window.createOutputChannel(`${CLIENT_NAME} Trace`);
  context.subscriptions.push(output, traceOutput);

  const diagrams = new DiagramViews({ request: requestDiagrams, languages: LANGUAGES });
  context.subscriptions.push(
    vscode.commands.registerCommand("robosim.restartServer", restart),
    vscode.commands.registerCommand("robosim.showOutput", () => output.show(true)),
    diagrams,
    // Client-side: not in the server's executeCommandProvider.
    vscode.commands.registerCommand(SHOW_DIAGRAM, (uri?: unknown, element?: unknown) => diagrams.show(uri, element)),
  );

  // `.rst`: switch documents that look like RoboSim (see rst-detect.ts).
  const switcher = new RstSwitcher();
  const examine = (doc: vscode.TextDocument): void => {
    if (doc.uri.scheme !== "file") return;
    const decide = switcher.shouldSwitch(
      {
        uri: doc.uri.toString(),
        fsPath: doc.uri.fsPath,
        languageId: doc.languageId,
        text: doc.getText(),
        detect: vscode.workspace.getConfiguration("robosim", doc.uri).get<boolean>("rst.detect", true),
        associations: vscode.workspace.getConfiguration("files", doc.uri).get<Record<string, unknown>>("associations"),
      },
      Date.now(),
    );
    if (decide) {
      log(`${doc.uri.fsPath} looks like RoboSim: opening it as RoboSim`);
      void vscode.languages.setTextDocumentLanguage(doc, "robosim");
    }
  };

  context.subscriptions.push(
    vscode.workspace.onDidOpenTextDocument((doc) => {
      examine(doc);
      if (isOurs(doc)) void ensureStarted();
    }),
    vscode.workspace.onDidCloseTextDocument((doc) => switcher.onDidClose(doc.uri.toString(), doc.languageId, Date.now())),
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (!e.affectsConfiguration("robosim.server.path")) return;
      if (gaveUp) {
        gaveUp = false;
        if (vscode.workspace.textDocuments.some(isOurs)) void ensureStarted();
      } else if (client || starting) {
        void vscode.window
          .showInformationMessage("robosim.server.path changed. Restart the RoboSim language server?", "Restart")
          .then((choice) => {
            if (choice) void restart();
          });
      }
    }),
  );

  for (const doc of vscode.workspace.textDocuments) {
    examine(doc);
    if (isOurs(doc)) void ensureStarted();
  }
}

export function deactivate(): Thenable<void> | undefined {
  return client ? stopClient() : undefined;
}
