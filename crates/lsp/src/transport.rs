//! The stdio transport: Content-Length framing, JSON-RPC message
//! classification, and one task per request.
//!
//! tower-lsp-server ships a transport (`Server::serve`), but its reader is
//! a `tokio_util` `FramedRead`, which ends the stream after the first
//! decoding error: one malformed message (bad JSON, a bad header) and the
//! server stops reading and exits. This loop answers such messages with a
//! JSON-RPC error (`-32700` parse error, `-32600` invalid request) and goes
//! on reading. Everything else, the protocol's state machine included, is
//! tower-lsp-server's `LspService`, driven through the same `tower::Service`
//! interface: `call` once per message, in wire order. Requests then run
//! concurrently, each in a task of its own; notifications run to completion
//! before the next message is read.

use futures::{SinkExt, StreamExt};
use serde_json::{json, Value};
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};
use tokio::sync::mpsc;
use tower::Service;
use tower_lsp_server::jsonrpc::{Request, Response};
use tower_lsp_server::ClientSocket;

use crate::ordered::Ordered;

/// Bodies larger than this are refused: no model needs them, and a bogus
/// length must not make the server allocate without bound.
const MAX_BODY: usize = 256 << 20;
/// Headers longer than this are garbage.
const MAX_HEADER: usize = 8 << 10;

enum Out {
    Message(Vec<u8>),
    /// Flush and stop: everything queued before it is written.
    Stop,
}

/// Serves until `exit` or the end of `input`.
pub(crate) async fn serve<I, O>(input: I, output: O, mut service: Ordered, socket: ClientSocket)
where
    I: AsyncRead + Unpin,
    O: AsyncWrite + Unpin + Send + 'static,
{
    let (out_tx, out_rx) = mpsc::unbounded_channel::<Out>();
    let writer = tokio::spawn(write_loop(output, out_rx));

    // Server-to-client requests and notifications (publishDiagnostics,
    // logMessage, registerCapability, …) go out through the same writer.
    let (mut client_requests, mut client_responses) = socket.split();
    let forward_tx = out_tx.clone();
    let forwarder = tokio::spawn(async move {
        while let Some(req) = client_requests.next().await {
            if let Ok(body) = serde_json::to_vec(&req) {
                let _ = forward_tx.send(Out::Message(body));
            }
        }
    });

    let mut reader = Reader { input, buf: Vec::with_capacity(64 << 10), eof: false, resync: false };
    loop {
        let body = match reader.next_body().await {
            Ok(Some(body)) => body,
            Ok(None) => break,
            Err(FrameError(message)) => {
                send_error(&out_tx, Value::Null, -32700, &message);
                continue;
            }
        };
        match classify(&body) {
            Incoming::Request(req) => {
                let will_exit = req.method() == "exit";
                if std::future::poll_fn(|cx| service.poll_ready(cx)).await.is_err() {
                    break;
                }
                let is_notification = req.id().is_none();
                let fut = service.call(req);
                if is_notification {
                    // Notifications are handled to the end, in order, before
                    // the next message: their handlers only update state and
                    // start background work, so this never waits long, and a
                    // request that follows a notification sees its effect.
                    let _ = fut.await;
                    if will_exit {
                        break;
                    }
                    continue;
                }
                let tx = out_tx.clone();
                tokio::spawn(async move {
                    if let Ok(Some(response)) = fut.await {
                        if let Ok(body) = serde_json::to_vec(&response) {
                            let _ = tx.send(Out::Message(body));
                        }
                    }
                });
                if will_exit {
                    break;
                }
            }
            Incoming::Response(res) => {
                if client_responses.send(res).await.is_err() {
                    break;
                }
            }
            Incoming::Invalid { id, code, message } => send_error(&out_tx, id, code, &message),
        }
    }
    forwarder.abort();
    let _ = out_tx.send(Out::Stop);
    let _ = writer.await;
}

fn send_error(tx: &mpsc::UnboundedSender<Out>, id: Value, code: i64, message: &str) {
    let body = json!({"jsonrpc": "2.0", "error": {"code": code, "message": message}, "id": id});
    let _ = tx.send(Out::Message(body.to_string().into_bytes()));
}

async fn write_loop<O: AsyncWrite + Unpin>(mut output: O, mut rx: mpsc::UnboundedReceiver<Out>) {
    while let Some(out) = rx.recv().await {
        match out {
            Out::Message(body) => {
                let header = format!("Content-Length: {}\r\n\r\n", body.len());
                if output.write_all(header.as_bytes()).await.is_err() || output.write_all(&body).await.is_err() {
                    return;
                }
                // Batch flushes when messages queue up, but never leave one
                // waiting.
                if rx.is_empty() && output.flush().await.is_err() {
                    return;
                }
            }
            Out::Stop => break,
        }
    }
    let _ = output.flush().await;
}

/// What a message body turned out to be.
enum Incoming {
    Request(Request),
    Response(Response),
    Invalid { id: Value, code: i64, message: String },
}

fn classify(body: &[u8]) -> Incoming {
    let value: Value = match serde_json::from_slice(body) {
        Ok(v) => v,
        Err(e) => return Incoming::Invalid { id: Value::Null, code: -32700, message: format!("Parse error: {e}") },
    };
    // The id to answer with, when the message has a usable one.
    let id = match value.get("id") {
        Some(id @ (Value::Number(_) | Value::String(_))) => id.clone(),
        _ => Value::Null,
    };
    let invalid = |message: String| Incoming::Invalid { id: id.clone(), code: -32600, message };
    if !value.is_object() {
        return invalid("Invalid request: a message must be a JSON object".into());
    }
    if value.get("method").is_some() {
        return match serde_json::from_value::<Request>(value.clone()) {
            Ok(req) => Incoming::Request(req),
            Err(e) => invalid(format!("Invalid request: {e}")),
        };
    }
    if value.get("result").is_some() || value.get("error").is_some() {
        return match serde_json::from_value::<Response>(value.clone()) {
            Ok(res) => Incoming::Response(res),
            Err(e) => invalid(format!("Invalid response: {e}")),
        };
    }
    invalid("Invalid request: no `method`, `result` or `error`".into())
}

struct FrameError(String);

/// What resynchronising found.
enum Skip {
    /// The next `Content-Length` header.
    Found,
    /// A block of garbage ending in a blank line (its text).
    Garbage(String),
    /// The end of input.
    End,
}

struct Reader<I> {
    input: I,
    buf: Vec<u8>,
    eof: bool,
    /// After a framing error: drop input up to the next `Content-Length`
    /// before reading a header. Kept as state, not done at once, because
    /// the next header may not have arrived yet when the error is found.
    resync: bool,
}

impl<I: AsyncRead + Unpin> Reader<I> {
    /// Reads more input; false at the end.
    async fn fill(&mut self) -> bool {
        if self.eof {
            return false;
        }
        let mut chunk = [0u8; 64 << 10];
        match self.input.read(&mut chunk).await {
            Ok(0) | Err(_) => {
                self.eof = true;
                false
            }
            Ok(n) => {
                self.buf.extend_from_slice(&chunk[..n]);
                true
            }
        }
    }

    /// Drops bytes up to the next `Content-Length`, reading more input as
    /// needed. A complete block of garbage (ending in a blank line) met
    /// first is dropped and reported, as a header without `Content-Length`.
    async fn skip_garbage(&mut self) -> Skip {
        let needle = b"Content-Length";
        loop {
            let header = find(&self.buf, needle);
            let blank = find(&self.buf, b"\r\n\r\n");
            match (header, blank) {
                (Some(i), b) if b.is_none_or(|j| i < j) => {
                    self.buf.drain(..i);
                    self.resync = false;
                    return Skip::Found;
                }
                (_, Some(j)) => {
                    let text = String::from_utf8_lossy(&self.buf[..j]).into_owned();
                    self.buf.drain(..j + 4);
                    self.resync = false;
                    return Skip::Garbage(text);
                }
                _ => {
                    // Keep a tail that may be the start of the next header.
                    let keep = self.buf.len().min(needle.len() - 1);
                    self.buf.drain(..self.buf.len() - keep);
                    if !self.fill().await {
                        return Skip::End;
                    }
                }
            }
        }
    }

    /// The next message body; `Ok(None)` at the end of input.
    async fn next_body(&mut self) -> Result<Option<Vec<u8>>, FrameError> {
        if self.resync {
            match self.skip_garbage().await {
                Skip::Found => {}
                Skip::End => return Ok(None),
                Skip::Garbage(text) => {
                    return Err(FrameError(format!(
                        "Parse error: missing or invalid `Content-Length` in header {text:?}"
                    )))
                }
            }
        }
        let header_end = loop {
            if let Some(i) = find(&self.buf, b"\r\n\r\n") {
                break i;
            }
            if self.buf.len() > MAX_HEADER {
                // The start is garbage even if it reads `Content-Length`.
                self.buf.drain(..1);
                self.resync = true;
                return Err(FrameError("Parse error: no message header (`Content-Length: N` and a blank line)".into()));
            }
            if !self.fill().await {
                if self.buf.iter().all(u8::is_ascii_whitespace) {
                    return Ok(None);
                }
                self.buf.clear();
                return Err(FrameError("Parse error: the input ended inside a message header".into()));
            }
        };
        let header = String::from_utf8_lossy(&self.buf[..header_end]).into_owned();
        self.buf.drain(..header_end + 4);
        let mut length = None;
        for line in header.split("\r\n") {
            if let Some((name, value)) = line.split_once(':') {
                if name.trim().eq_ignore_ascii_case("content-length") {
                    length = value.trim().parse::<usize>().ok();
                }
            }
        }
        let Some(length) = length else {
            // The bad header is gone: what follows may be a good one.
            self.resync = true;
            return Err(FrameError(format!("Parse error: missing or invalid `Content-Length` in header {header:?}")));
        };
        if length > MAX_BODY {
            self.resync = true;
            return Err(FrameError(format!("Parse error: message of {length} bytes is too large")));
        }
        while self.buf.len() < length {
            if !self.fill().await {
                self.buf.clear();
                return Err(FrameError("Parse error: the input ended inside a message body".into()));
            }
        }
        Ok(Some(self.buf.drain(..length).collect()))
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn framed(body: &str) -> String {
        format!("Content-Length: {}\r\n\r\n{body}", body.len())
    }

    /// Input delivered in the given pieces, one per read, as a pipe may.
    struct Pieces(std::collections::VecDeque<Vec<u8>>);

    impl AsyncRead for Pieces {
        fn poll_read(
            mut self: std::pin::Pin<&mut Self>,
            _: &mut std::task::Context<'_>,
            buf: &mut tokio::io::ReadBuf<'_>,
        ) -> std::task::Poll<std::io::Result<()>> {
            if let Some(piece) = self.0.pop_front() {
                buf.put_slice(&piece);
            }
            std::task::Poll::Ready(Ok(()))
        }
    }

    async fn bodies(input: &str) -> Vec<Result<String, String>> {
        bodies_in_pieces(&[input]).await
    }

    async fn bodies_in_pieces(pieces: &[&str]) -> Vec<Result<String, String>> {
        let input = Pieces(pieces.iter().map(|p| p.as_bytes().to_vec()).collect());
        let mut r = Reader { input, buf: Vec::new(), eof: false, resync: false };
        let mut out = Vec::new();
        loop {
            match r.next_body().await {
                Ok(Some(b)) => out.push(Ok(String::from_utf8(b).unwrap())),
                Ok(None) => return out,
                Err(FrameError(m)) => out.push(Err(m)),
            }
        }
    }

    #[tokio::test]
    async fn framing_recovers_from_garbage() {
        let input = format!(
            "{}garbage without header\r\n\r\n{}Content-Type: x\r\n\r\n{}Content-Length: 3\r\n\r\nab",
            framed("{\"a\":1}"),
            framed("{}"),
            framed("[]")
        );
        let got = bodies(&input).await;
        assert_eq!(got[0], Ok("{\"a\":1}".to_string()));
        assert!(got[1].is_err(), "{got:?}");
        assert_eq!(got[2], Ok("{}".to_string()));
        assert!(got[3].is_err(), "{got:?}");
        assert_eq!(got[4], Ok("[]".to_string()));
        // Truncated body at the end of input.
        assert!(got[5].is_err());
        assert_eq!(got.len(), 6);
    }

    /// Garbage after a bad header, then a good frame that arrives in a later
    /// read: the good frame is found (this once lost a request).
    #[tokio::test]
    async fn resynchronises_on_input_that_arrives_later() {
        let good = framed("{\"id\":1}");
        let got = bodies_in_pieces(&["Content-Length: abc\r\n\r\n{}", &good, "Content", &good[7..]]).await;
        assert!(got[0].is_err(), "{got:?}");
        assert_eq!(got[1], Ok("{\"id\":1}".to_string()));
        assert_eq!(got[2], Ok("{\"id\":1}".to_string()));
        assert_eq!(got.len(), 3, "{got:?}");
    }

    #[test]
    fn classification() {
        assert!(matches!(classify(b"{bad"), Incoming::Invalid { code: -32700, .. }));
        assert!(matches!(classify(b"[1]"), Incoming::Invalid { code: -32600, .. }));
        assert!(
            matches!(classify(br#"{"jsonrpc":"1.0","id":4,"method":"x"}"#), Incoming::Invalid { code: -32600, id, .. } if id == 4)
        );
        assert!(matches!(classify(br#"{"jsonrpc":"2.0","id":4,"method":"x"}"#), Incoming::Request(_)));
        assert!(matches!(classify(br#"{"jsonrpc":"2.0","id":4,"result":null}"#), Incoming::Response(_)));
        assert!(matches!(classify(br#"{"jsonrpc":"2.0","id":4}"#), Incoming::Invalid { code: -32600, .. }));
    }
}
