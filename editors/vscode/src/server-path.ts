// Where the `robosim` executable comes from. No `vscode` import here, so the
// tests run this module in plain Node.

import * as fs from "fs";
import * as os from "os";
import * as path from "path";

/** How the server binary was found. */
export type ServerSource = "setting" | "bundled" | "path";

export type Resolution =
  | { ok: true; command: string; source: ServerSource }
  | { ok: false; reason: "setting-not-found" | "not-found"; message: string };

/** What the search looks at; the defaults read the real machine. */
export interface SearchEnvironment {
  /** The `robosim.server.path` setting (user settings only: machine scope). */
  configured?: string | null;
  /** The extension's install folder, which may hold `server/robosim[.exe]`. */
  extensionPath: string;
  platform?: NodeJS.Platform;
  /** `PATH`; `undefined` means the process's. */
  pathVariable?: string;
  /** `PATHEXT` on Windows; `undefined` means the process's. */
  pathExt?: string;
  homeDir?: string;
  isExecutableFile?: (file: string) => boolean;
}

/** The executable's file name on a platform. */
export function binaryName(platform: NodeJS.Platform = process.platform): string {
  return platform === "win32" ? "robosim.exe" : "robosim";
}

function defaultIsExecutableFile(platform: NodeJS.Platform): (file: string) => boolean {
  return (file) => {
    try {
      const st = fs.statSync(file);
      if (!st.isFile()) return false;
      if (platform === "win32") return true;
      fs.accessSync(file, fs.constants.X_OK);
      return true;
    } catch {
      return false;
    }
  };
}

function expandHome(p: string, home: string): string {
  if (p === "~") return home;
  if (p.startsWith("~/") || p.startsWith("~\\")) return path.join(home, p.slice(2));
  return p;
}

/**
 * Looks `name` up on `PATH`. Only absolute entries count: an empty or relative
 * entry would resolve against the current folder, which may be an untrusted
 * workspace. The result is absolute, so spawning it never searches again.
 */
export function searchPath(
  name: string,
  pathVariable: string,
  platform: NodeJS.Platform,
  isExecutableFile: (file: string) => boolean,
  pathExt = "",
): string | undefined {
  const p = platform === "win32" ? path.win32 : path.posix;
  const sep = platform === "win32" ? ";" : ":";
  const names = [name];
  if (platform === "win32" && p.extname(name) === "") {
    const exts = (pathExt || ".COM;.EXE;.BAT;.CMD").split(";").filter((e) => e !== "");
    names.unshift(...exts.map((e) => name + e.toLowerCase()));
  }
  for (const raw of pathVariable.split(sep)) {
    const dir = raw.replace(/^"(.*)"$/, "$1");
    if (dir === "" || !p.isAbsolute(dir)) continue;
    for (const n of names) {
      const candidate = p.join(dir, n);
      if (isExecutableFile(candidate)) return candidate;
    }
  }
  return undefined;
}

/**
 * Finds the server: the `robosim.server.path` setting, then the binary
 * bundled in the extension (`server/robosim` or `server/robosim.exe`), then
 * `robosim` on `PATH`. A setting that names a missing file is an error: it
 * does not fall back to another binary.
 */
export function resolveServer(env: SearchEnvironment): Resolution {
  const platform = env.platform ?? process.platform;
  const isExec = env.isExecutableFile ?? defaultIsExecutableFile(platform);
  const home = env.homeDir ?? os.homedir();
  const pathVariable = env.pathVariable ?? process.env.PATH ?? "";
  const pathExt = env.pathExt ?? process.env.PATHEXT ?? "";
  const p = platform === "win32" ? path.win32 : path.posix;

  const configured = (env.configured ?? "").trim();
  if (configured !== "") {
    const expanded = expandHome(configured, home);
    if (p.isAbsolute(expanded)) {
      if (isExec(expanded)) return { ok: true, command: expanded, source: "setting" };
    } else if (!/[\\/]/.test(expanded)) {
      // A bare command name: looked up on PATH, like a shell would.
      const found = searchPath(expanded, pathVariable, platform, isExec, pathExt);
      if (found) return { ok: true, command: found, source: "setting" };
    }
    return {
      ok: false,
      reason: "setting-not-found",
      message:
        `robosim.server.path is set to "${configured}", but that is not an executable file` +
        (p.isAbsolute(expanded) || !/[\\/]/.test(expanded) ? "." : " (use an absolute path)."),
    };
  }

  const bundled = p.join(env.extensionPath, "server", binaryName(platform));
  if (isExec(bundled)) return { ok: true, command: bundled, source: "bundled" };

  const onPath = searchPath("robosim", pathVariable, platform, isExec, pathExt);
  if (onPath) return { ok: true, command: onPath, source: "path" };

  return {
    ok: false,
    reason: "not-found",
    message:
      "The RoboSim language server was not found: `robosim.server.path` is not set, this extension has no " +
      "bundled server, and there is no `robosim` on PATH. Install robosim (`cargo install --path crates/cli` " +
      "in the robosim repository) or set `robosim.server.path` in your user settings.",
  };
}
