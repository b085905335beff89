// Packages the extension into dist/robosim-<version>.vsix with @vscode/vsce.
// vsce runs the `vscode:prepublish` script (scripts/build.mjs) first, which
// copies the grammars and bundles the code, so the .vsix never depends on
// files left over from an earlier build.
//
// ROBOSIM_SERVER_BINARY=/path/to/robosim bundles that binary as
// server/robosim (server/robosim.exe if it ends in .exe); pass vsce options
// after `--`, e.g. `npm run package -- --target linux-x64` for a
// platform-specific .vsix. Without it no server is bundled and the extension
// uses robosim.server.path or PATH.
import { spawnSync } from "node:child_process";
import { chmodSync, copyFileSync, mkdirSync, readFileSync, rmSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const pkg = JSON.parse(readFileSync(join(root, "package.json"), "utf8"));

const serverDir = join(root, "server");
rmSync(serverDir, { recursive: true, force: true });
const bundled = process.env.ROBOSIM_SERVER_BINARY;
if (bundled) {
  mkdirSync(serverDir, { recursive: true });
  const name = bundled.toLowerCase().endsWith(".exe") ? "robosim.exe" : "robosim";
  copyFileSync(bundled, join(serverDir, name));
  chmodSync(join(serverDir, name), 0o755);
  console.log(`package: bundling ${bundled} as server/${name}`);
}

mkdirSync(join(root, "dist"), { recursive: true });
const out = join(root, "dist", `${pkg.name}-${pkg.version}.vsix`);
const vsce = join(root, "node_modules", "@vscode", "vsce", "vsce");
const args = [
  vsce,
  "package",
  "--no-dependencies", // esbuild bundled them into out/extension.js
  "--skip-license", // no LICENSE file: the licence is in package.json
  "--allow-missing-repository",
  "--out",
  out,
  ...process.argv.slice(2),
];
const r = spawnSync(process.execPath, args, { cwd: root, stdio: ["ignore", "inherit", "inherit"] });
if (r.status !== 0) {
  console.error(`package: vsce failed (exit status ${r.status ?? r.signal})`);
  process.exit(1);
}
console.log(`package: ${out}`);
