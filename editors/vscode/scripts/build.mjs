// Builds the extension: copies the TextMate grammars from ../../syntax (their
// only source; copies are never committed) into syntaxes/, and bundles
// src/extension.ts with esbuild into out/extension.js. It also bundles the
// vscode-free modules the Node tests load into out/test/.
// `vsce package` runs this as the `vscode:prepublish` script.
import { build } from "esbuild";
import { copyFileSync, existsSync, mkdirSync, readdirSync, rmSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const syntaxDir = join(root, "..", "..", "syntax");
const grammars = [
  "robochart.tmLanguage.json",
  "robosim.tmLanguage.json",
  "robochart-assertions.tmLanguage.json",
  "robosim-assertions.tmLanguage.json",
];

const missing = grammars.filter((g) => !existsSync(join(syntaxDir, g)));
if (missing.length > 0) {
  console.error(`build: grammars not found in ${syntaxDir}: ${missing.join(", ")}`);
  console.error("build: the extension is built from a robosim checkout (editors/vscode beside syntax/)");
  process.exit(1);
}
const syntaxesOut = join(root, "syntaxes");
rmSync(syntaxesOut, { recursive: true, force: true });
mkdirSync(syntaxesOut, { recursive: true });
for (const g of grammars) copyFileSync(join(syntaxDir, g), join(syntaxesOut, g));

rmSync(join(root, "out"), { recursive: true, force: true });
const common = {
  bundle: true,
  platform: "node",
  format: "cjs",
  target: "node18",
  logLevel: "warning",
};
await build({
  ...common,
  entryPoints: [join(root, "src", "extension.ts")],
  outfile: join(root, "out", "extension.js"),
  minify: true,
  keepNames: true,
  external: ["vscode"],
});
await build({
  ...common,
  entryPoints: [join(root, "src", "server-path.ts"), join(root, "src", "rst-detect.ts")],
  outdir: join(root, "out", "test"),
});
// The diagram view, for tests that give it a stand-in for `vscode`.
await build({
  ...common,
  entryPoints: [join(root, "src", "diagram.ts")],
  outdir: join(root, "out", "test"),
  external: ["vscode"],
});

const built = readdirSync(syntaxesOut).length;
console.log(`build: ${built} grammars copied from syntax/, out/extension.js bundled`);
