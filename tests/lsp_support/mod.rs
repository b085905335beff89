//! A client for end-to-end tests of `robosim lsp`: spawns the real binary,
//! speaks JSON-RPC with Content-Length framing over its stdio, and collects
//! what the server sends on a reader thread.

#![allow(dead_code)] // Each test binary uses a different part.

use std::io::{BufReader, Write};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use robosim_test_support::lsp_framing::{frame, read_message};

/// How long to wait for any one expected message. Generous: CI machines
/// are slow, and a passing test never waits this long.
pub const TIMEOUT: Duration = Duration::from_secs(20);

/// A running server and what it has sent that nobody consumed yet.
pub struct Server {
    child: Child,
    stdin: Option<ChildStdin>,
    rx: Receiver<Value>,
    /// Received, not yet matched by an expectation.
    pub pending: Vec<Value>,
    /// Replies to server requests, by method (default: `null`).
    pub replies: Vec<(String, Value)>,
    /// Every server-to-client request seen, in order.
    pub server_requests: Vec<Value>,
    /// Every message received, in order.
    pub log: Vec<Value>,
    next_id: i64,
}

impl Server {
    /// Starts `robosim lsp`.
    pub fn start() -> Server {
        Server::start_with_args(&[])
    }

    /// Starts `robosim lsp` with extra arguments after `lsp`.
    pub fn start_with_args(args: &[&str]) -> Server {
        Server::start_with_env(args, &[])
    }

    /// Starts `robosim lsp` with extra arguments and environment variables.
    pub fn start_with_env(args: &[&str], env: &[(&str, &str)]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_robosim-e2e"))
            .arg("lsp")
            .args(args)
            .envs(env.iter().copied())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("cannot start robosim lsp");
        let stdout = child.stdout.take().unwrap();
        let stdin = child.stdin.take();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            while let Some(msg) = read_message(&mut reader) {
                if tx.send(msg).is_err() {
                    return;
                }
            }
        });
        Server {
            child,
            stdin,
            rx,
            pending: Vec::new(),
            replies: Vec::new(),
            server_requests: Vec::new(),
            log: Vec::new(),
            next_id: 1000,
        }
    }

    /// Writes raw bytes to the server.
    pub fn send_raw(&mut self, bytes: &[u8]) {
        if let Some(stdin) = self.stdin.as_mut() {
            let _ = stdin.write_all(bytes);
            let _ = stdin.flush();
        }
    }

    /// Sends one message, framed.
    pub fn send(&mut self, msg: &Value) {
        self.send_raw(frame(msg).as_bytes());
    }

    pub fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// Sends a request and returns its id.
    pub fn request(&mut self, method: &str, params: Value) -> i64 {
        self.next_id += 1;
        let id = self.next_id;
        self.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        id
    }

    /// Sends a request and waits for its response.
    pub fn call(&mut self, method: &str, params: Value) -> Value {
        let id = self.request(method, params);
        self.expect(&json!({"id": id}))
    }

    /// Receives one message (answering server requests on the way);
    /// `None` after `timeout`.
    fn receive(&mut self, timeout: Duration) -> Option<Value> {
        match self.rx.recv_timeout(timeout) {
            Ok(msg) => {
                self.log.push(msg.clone());
                if msg.get("method").is_some() && msg.get("id").is_some() {
                    let method = msg["method"].as_str().unwrap_or_default().to_string();
                    let result =
                        self.replies.iter().find(|(m, _)| *m == method).map(|(_, v)| v.clone()).unwrap_or(Value::Null);
                    let reply = json!({"jsonrpc": "2.0", "id": msg["id"].clone(), "result": result});
                    self.server_requests.push(msg.clone());
                    self.send(&reply);
                }
                Some(msg)
            }
            Err(RecvTimeoutError::Timeout) | Err(RecvTimeoutError::Disconnected) => None,
        }
    }

    /// Waits for a message matching `pattern` (see [`matches`]); messages
    /// received meanwhile stay pending for later expectations, so the order
    /// of notifications does not matter. Panics after [`TIMEOUT`].
    pub fn expect(&mut self, pattern: &Value) -> Value {
        self.try_expect(pattern, TIMEOUT).unwrap_or_else(|| {
            panic!(
                "no message matching\n{pattern:#}\nwithin {TIMEOUT:?}; pending:\n{}",
                self.pending.iter().map(|m| m.to_string()).collect::<Vec<_>>().join("\n")
            )
        })
    }

    pub fn try_expect(&mut self, pattern: &Value, timeout: Duration) -> Option<Value> {
        if let Some(i) = self.pending.iter().position(|m| matches(pattern, m)) {
            return Some(self.pending.remove(i));
        }
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.checked_duration_since(Instant::now())?;
            let msg = self.receive(left)?;
            if matches(pattern, &msg) {
                return Some(msg);
            }
            self.pending.push(msg);
        }
    }

    /// Collects everything that arrives within `quiet` of silence.
    pub fn drain(&mut self, quiet: Duration) {
        while let Some(msg) = self.receive(quiet) {
            self.pending.push(msg);
        }
    }

    /// `initialize` with the given capabilities and folders, then
    /// `initialized`.
    pub fn initialize(&mut self, capabilities: Value, folders: Value) -> Value {
        let result = self.call("initialize", json!({"capabilities": capabilities, "workspaceFolders": folders}));
        self.notify("initialized", json!({}));
        result
    }

    /// Closes stdin (the end of input).
    pub fn close_stdin(&mut self) {
        self.stdin = None;
    }

    /// Waits for the process to end.
    pub fn wait_exit(&mut self, timeout: Duration) -> Option<ExitStatus> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Ok(Some(status)) = self.child.try_wait() {
                return Some(status);
            }
            if Instant::now() > deadline {
                return None;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Whether the process is still running.
    pub fn alive(&mut self) -> bool {
        matches!(self.child.try_wait(), Ok(None))
    }

    /// `shutdown`, `exit`, and the exit status 0.
    pub fn shutdown(mut self) {
        let res = self.call("shutdown", Value::Null);
        assert_eq!(res.get("result"), Some(&Value::Null), "{res}");
        self.notify("exit", Value::Null);
        let status = self.wait_exit(TIMEOUT).expect("the server did not exit");
        assert_eq!(status.code(), Some(0));
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        if self.alive() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Whether `actual` matches `pattern`: objects match when every key of the
/// pattern matches (extra keys are ignored), arrays element by element with
/// the same length, `"$any"` matches anything present, `"$absent"` a
/// missing key, and other values by equality.
pub fn matches(pattern: &Value, actual: &Value) -> bool {
    match (pattern, actual) {
        (Value::String(s), _) if s == "$any" => true,
        (Value::Object(p), Value::Object(a)) => p.iter().all(|(k, pv)| match a.get(k) {
            Some(av) => matches(pv, av),
            None => pv == "$absent",
        }),
        (Value::Array(p), Value::Array(a)) => p.len() == a.len() && p.iter().zip(a).all(|(p, a)| matches(p, a)),
        _ => pattern == actual,
    }
}

/// A file URI for `path`.
pub fn uri(path: &std::path::Path) -> String {
    let s = path.to_string_lossy().replace('\\', "/");
    if s.starts_with('/') {
        format!("file://{s}")
    } else {
        format!("file:///{s}")
    }
}

/// A fresh temporary folder for one test.
pub fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("robosim-lsp-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
