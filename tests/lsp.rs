//! `ger lsp` as an editor meets it: a scripted client opens a document,
//! changes it, asks for inlay hints, and reads what the server publishes,
//! over an in-memory connection (and once through the binary on stdio).

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use lsp_server::{Connection, Message, Notification, Request, RequestId};
use lsp_types::notification::{
    DidChangeTextDocument, DidOpenTextDocument, Exit, Initialized, Notification as _,
    PublishDiagnostics,
};
use lsp_types::request::{Initialize, InlayHintRequest, Request as _, Shutdown};
use lsp_types::{
    DidChangeTextDocumentParams, DidOpenTextDocumentParams, InlayHint, InlayHintParams, Position,
    PublishDiagnosticsParams, Range, TextDocumentContentChangeEvent, TextDocumentIdentifier,
    TextDocumentItem, VersionedTextDocumentIdentifier,
};
use std::time::Duration;

/// A client on one end of a connection, the server on the other.
struct Client {
    connection: Connection,
    server: Option<std::thread::JoinHandle<()>>,
    next_id: i32,
}

impl Client {
    fn start() -> Client {
        let (server, client) = Connection::memory();
        let handle = std::thread::spawn(move || ger::lsp::serve(&server).unwrap());
        let mut c = Client {
            connection: client,
            server: Some(handle),
            next_id: 0,
        };
        let init = serde_json::json!({ "capabilities": {}, "processId": null, "rootUri": null });
        let answer = c.request(Initialize::METHOD, init);
        assert!(
            answer["capabilities"]["inlayHintProvider"] == true,
            "{answer}"
        );
        c.notify(Initialized::METHOD, serde_json::json!({}));
        c
    }

    fn notify(&self, method: &str, params: impl serde::Serialize) {
        let n = Notification::new(method.into(), params);
        self.connection
            .sender
            .send(Message::Notification(n))
            .unwrap();
    }

    fn request(&mut self, method: &str, params: impl serde::Serialize) -> serde_json::Value {
        self.next_id += 1;
        let id = RequestId::from(self.next_id);
        let r = Request::new(id.clone(), method.into(), params);
        self.connection.sender.send(Message::Request(r)).unwrap();
        loop {
            match self.receive() {
                Message::Response(r) if r.id == id => return r.result.unwrap_or_default(),
                _ => continue,
            }
        }
    }

    fn receive(&self) -> Message {
        self.connection
            .receiver
            .recv_timeout(Duration::from_secs(20))
            .expect("the server answers")
    }

    /// The next diagnostics published.
    fn diagnostics(&self) -> PublishDiagnosticsParams {
        loop {
            if let Message::Notification(n) = self.receive() {
                if n.method == PublishDiagnostics::METHOD {
                    return serde_json::from_value(n.params).unwrap();
                }
            }
        }
    }

    fn stop(mut self) {
        self.request(Shutdown::METHOD, serde_json::Value::Null);
        self.notify(Exit::METHOD, serde_json::Value::Null);
        self.server.take().unwrap().join().unwrap();
    }
}

fn uri(path: &str) -> lsp_types::Uri {
    ger::lsp::uri_of(std::path::Path::new(path)).unwrap()
}

#[test]
fn diagnostics_come_on_open_go_when_fixed_and_hints_say_where_the_tool_is() {
    let mut client = Client::start();
    let doc = uri("/nowhere/a part.egc");
    let broken = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\nG1 X<Width>\nM30\n";
    client.notify(
        DidOpenTextDocument::METHOD,
        DidOpenTextDocumentParams {
            text_document: TextDocumentItem::new(doc.clone(), "gcode".into(), 1, broken.into()),
        },
    );
    let published = client.diagnostics();
    assert_eq!(published.uri, doc);
    assert_eq!(published.version, Some(1));
    let errors: Vec<_> = published
        .diagnostics
        .iter()
        .filter(|d| d.severity == Some(lsp_types::DiagnosticSeverity::ERROR))
        .collect();
    assert_eq!(errors.len(), 1, "{:?}", published.diagnostics);
    assert_eq!(errors[0].range.start.line, 3);
    assert!(errors[0].message.contains("Width"), "{}", errors[0].message);

    // Three changes sent at once: what is published last is the newest's
    // (the server reads what waits before it analyses, so it usually
    // skips the first two; the test does not depend on the timing).
    for (version, text) in [(2, "G21\nX<"), (3, "G21\nX<<"), (4, "Width = 12\n")] {
        client.notify(
            DidChangeTextDocument::METHOD,
            DidChangeTextDocumentParams {
                text_document: VersionedTextDocumentIdentifier::new(doc.clone(), version),
                content_changes: vec![TextDocumentContentChangeEvent {
                    range: None,
                    range_length: None,
                    text: format!("{text}{broken}"),
                }],
            },
        );
    }
    let mut published = client.diagnostics();
    while published.version != Some(4) {
        published = client.diagnostics();
    }
    assert!(
        published
            .diagnostics
            .iter()
            .all(|d| d.severity != Some(lsp_types::DiagnosticSeverity::ERROR)),
        "{:?}",
        published.diagnostics
    );
    let hints = client.request(
        InlayHintRequest::METHOD,
        InlayHintParams {
            text_document: TextDocumentIdentifier::new(doc.clone()),
            range: Range::new(Position::new(0, 0), Position::new(100, 0)),
            work_done_progress_params: Default::default(),
        },
    );
    let hints: Vec<InlayHint> = serde_json::from_value(hints).unwrap();
    let labels: Vec<String> = hints
        .iter()
        .map(|h| match &h.label {
            lsp_types::InlayHintLabel::String(s) => format!("{}: {s}", h.position.line),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(
        labels,
        [
            "2: → X0 Y0 Z5 · 0:00",
            "3: → X0 Y0 Z-1 · 0:01",
            "4: → X12 Y0 Z-1 · 0:02"
        ]
    );
    // The outline of a program with a subprogram and a tool change.
    let fanuc = uri("/nowhere/sub.nc");
    client.notify(
        DidOpenTextDocument::METHOD,
        DidOpenTextDocumentParams {
            text_document: TextDocumentItem::new(
                fanuc.clone(),
                "gcode".into(),
                1,
                "G21 G90\nT2 M6\nM98 P100\nM30\nO100\nG0 X1\nM99\n".into(),
            ),
        },
    );
    let mut published = client.diagnostics();
    while published.uri != fanuc {
        published = client.diagnostics();
    }
    let symbols = client.request(
        lsp_types::request::DocumentSymbolRequest::METHOD,
        serde_json::json!({ "textDocument": { "uri": fanuc.as_str() } }),
    );
    let names: Vec<_> = symbols
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["name"].as_str().unwrap().to_string(),
                s["range"]["start"]["line"].clone(),
            )
        })
        .collect();
    assert_eq!(
        names,
        [
            ("T2 (tool change)".to_string(), serde_json::json!(1)),
            ("O100".to_string(), serde_json::json!(4))
        ]
    );
    // Hovering G1 on line 3 (`G1 Z-1 F600`, after the line added above).
    let hover = client.request(
        lsp_types::request::HoverRequest::METHOD,
        serde_json::json!({
            "textDocument": { "uri": doc.as_str() },
            "position": { "line": 3, "character": 1 }
        }),
    );
    let shown = hover["contents"]["value"].as_str().unwrap_or_default();
    assert!(shown.starts_with("**G1**: straight feed move"), "{hover}");
    client.stop();
}

/// Through the binary, on stdio, as an editor starts it.
#[test]
fn the_binary_speaks_lsp_on_stdio() {
    use std::io::{BufRead, BufReader, Read, Write};
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("lsp")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut send = |value: serde_json::Value| {
        let body = value.to_string();
        write!(stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
        stdin.flush().unwrap();
    };
    let mut receive = || -> serde_json::Value {
        let mut length = 0;
        loop {
            let mut line = String::new();
            stdout.read_line(&mut line).unwrap();
            if line == "\r\n" {
                break;
            }
            if let Some(n) = line.strip_prefix("Content-Length: ") {
                length = n.trim().parse().unwrap();
            }
        }
        let mut body = vec![0; length];
        stdout.read_exact(&mut body).unwrap();
        serde_json::from_slice(&body).unwrap()
    };
    send(
        serde_json::json!({"jsonrpc": "2.0", "id": 1, "method": "initialize",
        "params": {"capabilities": {}, "processId": null, "rootUri": null}}),
    );
    let init = receive();
    assert_eq!(init["id"], 1, "{init}");
    send(serde_json::json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}));
    send(
        serde_json::json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {
        "textDocument": {"uri": "file:///nowhere/b.nc", "languageId": "gcode", "version": 7,
                         "text": "G21\nG1 X10 F100\nG5 X1\nM30\n"}}}),
    );
    let published = receive();
    assert_eq!(
        published["method"], "textDocument/publishDiagnostics",
        "{published}"
    );
    assert_eq!(published["params"]["version"], 7);
    let lines: Vec<_> = published["params"]["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["severity"] == 1)
        .map(|d| d["range"]["start"]["line"].clone())
        .collect();
    assert_eq!(lines, [serde_json::json!(2)], "{published}");
    send(serde_json::json!({"jsonrpc": "2.0", "id": 2, "method": "shutdown"}));
    assert_eq!(receive()["id"], 2);
    send(serde_json::json!({"jsonrpc": "2.0", "method": "exit"}));
    assert!(child.wait().unwrap().success());
}
