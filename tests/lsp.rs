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
use lsp_types::request::{HoverRequest, Initialize, InlayHintRequest, Request as _, Shutdown};
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

impl Client {
    /// Open `text` as `uri` and wait for its diagnostics.
    fn open(&self, uri: &lsp_types::Uri, text: &str) -> PublishDiagnosticsParams {
        self.notify(
            DidOpenTextDocument::METHOD,
            DidOpenTextDocumentParams {
                text_document: TextDocumentItem::new(uri.clone(), "gcode".into(), 1, text.into()),
            },
        );
        loop {
            let published = self.diagnostics();
            if &published.uri == uri {
                return published;
            }
        }
    }

    /// Ask `method` about the place `line`:`column` of `uri`, with `more`
    /// parameters.
    fn ask(
        &mut self,
        method: &str,
        uri: &lsp_types::Uri,
        (line, column): (u32, u32),
        more: serde_json::Value,
    ) -> serde_json::Value {
        let mut params = serde_json::json!({
            "textDocument": { "uri": uri.as_str() },
            "position": { "line": line, "character": column }
        });
        if let (Some(params), Some(more)) = (params.as_object_mut(), more.as_object()) {
            params.extend(more.clone());
        }
        self.request(method, params)
    }

    fn hover(&mut self, uri: &lsp_types::Uri, at: (u32, u32)) -> String {
        let answer = self.ask(HoverRequest::METHOD, uri, at, serde_json::json!({}));
        answer["contents"]["value"]
            .as_str()
            .unwrap_or_default()
            .to_string()
    }
}

/// Where each location of an answer is: its file's name and line.
fn places(answer: &serde_json::Value) -> Vec<(String, u64)> {
    answer
        .as_array()
        .unwrap_or(&Vec::new())
        .iter()
        .map(|l| {
            let uri = l["uri"].as_str().unwrap_or_default();
            let name = uri.rsplit('/').next().unwrap_or_default().to_string();
            (name, l["range"]["start"]["line"].as_u64().unwrap())
        })
        .collect()
}

const LOOP_PROGRAM: &str = "G21 G90\nDepth = 2\nCount = 0\nG0 X0 Y0 Z5\n\
    while (Count < 3) {\n  G1 X<Count * 6> F100\n  Count = Count + 1\n}\nG1 Z<-Depth>\n\
    Pocket 20 10 2\nM98 P100\nM30\nO100 (DRILL THE PATTERN)\nG0 X1\nM99\n";

#[test]
fn hover_shows_a_variables_values_a_wizards_manual_and_a_calls_comment() {
    let mut client = Client::start();
    let doc = uri("/nowhere/hover/part.egc");
    client.open(&doc, LOOP_PROGRAM);
    // `Count` in the loop's move: 0, 1, 2.
    let count = client.hover(&doc, (5, 8));
    assert_eq!(count, "`Count` varies here: 3 values, 0 … 2");
    // In the condition, tested four times; set to 1, 2, 3.
    assert_eq!(
        client.hover(&doc, (4, 8)),
        "`Count` varies here: 4 values, 0 … 3"
    );
    assert_eq!(
        client.hover(&doc, (6, 3)),
        "`Count` varies here: 3 values, 1 … 3"
    );
    assert_eq!(client.hover(&doc, (8, 7)), "`Depth` = 2 here");
    // The wizard's manual, as `ger wizards Pocket` prints it.
    let manual = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["wizards", "Pocket"])
        .output()
        .unwrap();
    let manual = String::from_utf8(manual.stdout).unwrap();
    assert!(manual.starts_with("Pocket width height depth"), "{manual}");
    assert_eq!(client.hover(&doc, (9, 2)), format!("```text\n{manual}```"));
    // The call's subprogram and its first comment.
    assert_eq!(client.hover(&doc, (10, 5)), "**O100**: DRILL THE PATTERN");
    // A change: the values are worked out again.
    client.notify(
        DidChangeTextDocument::METHOD,
        DidChangeTextDocumentParams {
            text_document: VersionedTextDocumentIdentifier::new(doc.clone(), 2),
            content_changes: vec![TextDocumentContentChangeEvent {
                range: None,
                range_length: None,
                text: LOOP_PROGRAM.replace("Depth = 2", "Depth = 2.5"),
            }],
        },
    );
    // Requests are answered from the last analysis until the new one is
    // published.
    while client.diagnostics().version != Some(2) {}
    assert_eq!(client.hover(&doc, (8, 7)), "`Depth` = 2.5 here");
    client.stop();
}

#[test]
fn definition_references_and_rename() {
    use lsp_types::request::{GotoDefinition, References, Rename};
    let mut client = Client::start();
    let doc = uri("/nowhere/nav/part.egc");
    client.open(&doc, LOOP_PROGRAM);
    let none = serde_json::json!({});
    let def = |c: &mut Client, at| places(&c.ask(GotoDefinition::METHOD, &doc, at, none.clone()));
    // M98 P100 -> O100; a variable -> its assignments.
    assert_eq!(def(&mut client, (10, 5)), [("part.egc".into(), 12)]);
    assert_eq!(
        def(&mut client, (5, 9)),
        [("part.egc".into(), 2), ("part.egc".into(), 6)]
    );
    let refs = client.ask(
        References::METHOD,
        &doc,
        (8, 6),
        serde_json::json!({ "context": { "includeDeclaration": true } }),
    );
    assert_eq!(
        places(&refs),
        [("part.egc".into(), 1), ("part.egc".into(), 8)]
    );
    // Rename `Depth` to `Cut`: both places.
    let edit = client.ask(
        Rename::METHOD,
        &doc,
        (1, 1),
        serde_json::json!({ "newName": "Cut" }),
    );
    let edits = edit["changes"][doc.as_str()].as_array().unwrap();
    let lines: Vec<_> = edits
        .iter()
        .map(|e| (e["range"]["start"]["line"].clone(), e["newText"].clone()))
        .collect();
    assert_eq!(
        lines,
        [
            (serde_json::json!(1), serde_json::json!("Cut")),
            (serde_json::json!(8), serde_json::json!("Cut"))
        ]
    );
    // A LinuxCNC subroutine in a file of its own, open in the editor;
    // a named parameter renamed keeps its `#<…>`.
    let sub = uri("/nowhere/nav/drill.ngc");
    client.open(
        &sub,
        "o<drill> sub\n(one hole)\nG0 X#1\no<drill> endsub\nM2\n",
    );
    let main = uri("/nowhere/nav/main.ngc");
    client.open(
        &main,
        "G21 G90\n#<depth> = 3\no<drill> call [#<depth>]\nG1 Z-#<depth> F100\nM2\n",
    );
    let found = client.ask(GotoDefinition::METHOD, &main, (2, 3), none.clone());
    assert_eq!(places(&found), [("drill.ngc".into(), 0)]);
    assert_eq!(client.hover(&main, (2, 3)), "**o<drill>**: one hole");
    let edit = client.ask(
        Rename::METHOD,
        &main,
        (3, 8),
        serde_json::json!({ "newName": "cut" }),
    );
    let texts: Vec<_> = edit["changes"][main.as_str()]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["newText"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(texts, ["#<cut>", "#<cut>", "#<cut>"]);
    // Fanuc's G65 P… -> its O block.
    let fanuc = uri("/nowhere/nav/macro.nc");
    client.open(
        &fanuc,
        "G21 G90\nG65 P200 A1 B2\nM30\nO200 (BOSS)\n#100=#1\nM99\n",
    );
    let found = client.ask(GotoDefinition::METHOD, &fanuc, (1, 6), none.clone());
    assert_eq!(places(&found), [("macro.nc".into(), 3)]);
    assert_eq!(client.hover(&fanuc, (1, 6)), "**O200**: BOSS");
    // A wizard call -> its .rhai file (a user wizard beside the part).
    let wizard = uri("/nowhere/nav/wizards/Hole.rhai");
    client.open(
        &wizard,
        "//! One hole.\n//! @param depth  how deep\nlinear(0.0, 0.0, -depth);\n",
    );
    let part = uri("/nowhere/nav/holes.egc");
    client.open(&part, "G21 G90\nG0 X0 Y0 Z5\nF100\nHole 3\nM30\n");
    let found = client.ask(GotoDefinition::METHOD, &part, (3, 1), none);
    assert_eq!(places(&found), [("Hole.rhai".into(), 0)]);
    client.stop();
}

#[test]
fn completion_and_signature_help() {
    use lsp_types::request::{Completion, SignatureHelpRequest};
    let mut client = Client::start();
    let doc = uri("/nowhere/complete/part.egc");
    let text = "G21 G90\nDepth = 2\nG8\n\nPocket 20 1\nPocket(20, \nG65 P100 A1 B\nM30\nO100 (BOSS)\nM99\n";
    client.open(&doc, text);
    let none = serde_json::json!({});
    let offered = |c: &mut Client, at| -> Vec<serde_json::Value> {
        let answer = c.ask(Completion::METHOD, &doc, at, serde_json::json!({}));
        answer.as_array().unwrap().clone()
    };
    let after_g8 = offered(&mut client, (2, 2));
    let g83 = after_g8.iter().find(|c| c["label"] == "G83").unwrap();
    assert_eq!(g83["detail"], "peck drilling, full retract");
    assert!(after_g8
        .iter()
        .all(|c| c["label"].as_str().unwrap().starts_with('G')));
    let fresh = offered(&mut client, (3, 0));
    let pocket = fresh.iter().find(|c| c["label"] == "Pocket").unwrap();
    assert_eq!(
        pocket["insertText"],
        "Pocket ${1:width} ${2:height} ${3:depth}"
    );
    assert_eq!(pocket["insertTextFormat"], 2);
    assert!(fresh
        .iter()
        .any(|c| c["label"] == "Depth" && c["kind"] == 6));
    let help = |c: &mut Client, at| c.ask(SignatureHelpRequest::METHOD, &doc, at, none.clone());
    let spaced = help(&mut client, (4, 11));
    assert_eq!(spaced["activeParameter"], 1, "{spaced}");
    let label = spaced["signatures"][0]["label"].as_str().unwrap();
    assert!(
        label.starts_with("Pocket width height depth [stepdown=0]"),
        "{label}"
    );
    assert_eq!(help(&mut client, (5, 11))["activeParameter"], 1);
    assert_eq!(help(&mut client, (4, 7))["activeParameter"], 0);
    let g65 = help(&mut client, (6, 13));
    let signature = &g65["signatures"][0];
    let active = g65["activeParameter"].as_u64().unwrap() as usize;
    assert_eq!(signature["parameters"][active]["label"], "B=#2", "{g65}");
    assert_eq!(signature["documentation"], "macro call of O100: BOSS");
    assert!(help(&mut client, (1, 3)).is_null());
    client.stop();
}

/// The tool path of `text` as the file `path`, by the library, without
/// its places in the text: what formatting must keep.
fn tool_path_of(path: &str, text: &str) -> Vec<String> {
    use ger::driver::{discovery::Search, fs::Memory, CompileOptions, Program, Session};
    let fs = Memory::new();
    let session = Session::new(&fs, CompileOptions::default(), Search::default()).unwrap();
    let program = Program::Text {
        name: path,
        path: Some(std::path::Path::new(path)),
        text: text.into(),
    };
    let Ok(mut job) = session.load(program) else {
        panic!("{path} loads")
    };
    let path = job.tool_path().0.expect("the program compiles");
    let moves = path
        .moves
        .iter()
        .map(|m| format!("{:?} {:?} {:?} {:?}", m.kind, m.start, m.end, m.state));
    let events = path
        .events
        .iter()
        .map(|e| format!("{:?} after {}", e.kind, e.after_move));
    moves.chain(events).collect()
}

#[test]
fn formatting_renumbers_spaces_and_cases_and_keeps_the_tool_path() {
    use lsp_types::request::Formatting;
    let mut client = Client::start();
    let doc = uri("/nowhere/format/messy.nc");
    let messy = "%\nn5 g21g90 g0x0 y0   z5\nN7 t1m6\ng1 z-1 f100 (CUT (DEEP))\n  g1  x10.  \n\
                 /n9 G1 Y5 ; end\nG2 X20 Y5 i5 j0\nm30\n%\n";
    client.open(&doc, messy);
    let format = |c: &mut Client, options: serde_json::Value| {
        c.request(
            Formatting::METHOD,
            serde_json::json!({ "textDocument": { "uri": doc.as_str() }, "options": options }),
        )
    };
    let edits = format(
        &mut client,
        serde_json::json!({ "tabSize": 4, "insertSpaces": true }),
    );
    let formatted = edits[0]["newText"].as_str().unwrap().to_string();
    assert_eq!(
        formatted,
        "%\nN10 G21 G90 G0 X0 Y0 Z5\nN20 T1 M6\nG1 Z-1 F100 (CUT (DEEP))\nG1 X10.\n\
         /N30 G1 Y5 ; end\nG2 X20 Y5 I5 J0\nM30\n%\n"
    );
    assert_eq!(
        edits[0]["range"]["start"],
        serde_json::json!({"line": 0, "character": 0})
    );
    let before = tool_path_of("/nowhere/format/messy.nc", messy);
    assert!(before.len() > 4, "{before:?}");
    assert_eq!(before, tool_path_of("/nowhere/format/messy.nc", &formatted));
    let removed = format(
        &mut client,
        serde_json::json!({ "tabSize": 4, "insertSpaces": true, "gerNumbers": "remove" }),
    );
    let removed = removed[0]["newText"].as_str().unwrap().to_string();
    assert!(
        removed.starts_with("%\nG21 G90 G0 X0 Y0 Z5\nT1 M6\n"),
        "{removed}"
    );
    assert_eq!(before, tool_path_of("/nowhere/format/messy.nc", &removed));
    // A program with an error is not formatted: its tool path could not
    // be checked.
    let broken = uri("/nowhere/format/broken.nc");
    client.open(&broken, "g21 g90\ng5 x1\nm30\n");
    client.next_id += 1;
    let id = RequestId::from(client.next_id);
    let request = Request::new(
        id.clone(),
        Formatting::METHOD.into(),
        serde_json::json!({ "textDocument": { "uri": broken.as_str() },
                            "options": { "tabSize": 4, "insertSpaces": true } }),
    );
    client
        .connection
        .sender
        .send(Message::Request(request))
        .unwrap();
    let refused = loop {
        if let Message::Response(r) = client.receive() {
            if r.id == id {
                break r.error.expect("an error");
            }
        }
    };
    assert!(refused.message.contains("compiles"), "{}", refused.message);
    client.stop();
}

impl Client {
    /// Send a request without waiting for its answer.
    fn send(&mut self, method: &str, params: impl serde::Serialize) -> RequestId {
        self.next_id += 1;
        let id = RequestId::from(self.next_id);
        let r = Request::new(id.clone(), method.into(), params);
        self.connection.sender.send(Message::Request(r)).unwrap();
        id
    }

    /// Change `uri`'s whole text to `text`, as its `version`.
    fn change(&self, uri: &lsp_types::Uri, version: i32, text: String) {
        self.notify(
            DidChangeTextDocument::METHOD,
            DidChangeTextDocumentParams {
                text_document: VersionedTextDocumentIdentifier::new(uri.clone(), version),
                content_changes: vec![TextDocumentContentChangeEvent {
                    range: None,
                    range_length: None,
                    text,
                }],
            },
        );
    }
}

/// What a client received, in order: a response's id, or the version of
/// the diagnostics published.
#[derive(Debug, PartialEq)]
enum Received {
    Answer(RequestId),
    Published(Option<i32>),
}

#[test]
fn a_long_program_blocks_nothing_and_a_change_cancels_its_analysis() {
    use lsp_types::request::{DocumentSymbolRequest, Formatting};
    let mut client = Client::start();
    let doc = uri("/nowhere/long/part.ngc");
    let mut long = String::from("G21 G90\n#<depth> = 1\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-#<depth> F600\n");
    for i in 0..200_000 {
        long.push_str(&format!("G1 X{} Y{}\n", i % 100, i / 100));
    }
    long.push_str("M2\n");
    let outline = serde_json::json!({ "textDocument": { "uri": doc.as_str() } });
    client.notify(
        DidOpenTextDocument::METHOD,
        DidOpenTextDocumentParams {
            text_document: TextDocumentItem::new(doc.clone(), "gcode".into(), 1, long.clone()),
        },
    );
    // Asked before the first analysis: answered when it is done, from it.
    let first = client.send(DocumentSymbolRequest::METHOD, outline.clone());
    let mut published = false;
    let symbols = loop {
        match client.receive() {
            Message::Notification(n) if n.method == PublishDiagnostics::METHOD => published = true,
            Message::Response(r) if r.id == first => break r.result.unwrap(),
            _ => {}
        }
    };
    assert!(published, "the analysis comes before the answer");
    assert_eq!(symbols[0]["name"], "T1 (tool change)", "{symbols}");
    // A hover on a variable: its values are a run of the whole program,
    // off the loop. Meanwhile a change (version 2, with an error), an
    // outline asked, a formatting asked and cancelled: the outline and
    // the cancel are answered at once, from the last analysis, before
    // the hover's values and version 2's analysis are done.
    let hover = client.send(
        HoverRequest::METHOD,
        serde_json::json!({ "textDocument": { "uri": doc.as_str() },
                            "position": { "line": 4, "character": 8 } }),
    );
    client.change(&doc, 2, long.replace("G1 X5 Y3\n", "G5 X5 Y3\n"));
    let outlined = client.send(DocumentSymbolRequest::METHOD, outline);
    let format = client.send(
        Formatting::METHOD,
        serde_json::json!({ "textDocument": { "uri": doc.as_str() },
                            "options": { "tabSize": 4, "insertSpaces": true } }),
    );
    client.notify(
        lsp_types::notification::Cancel::METHOD,
        serde_json::json!({ "id": client.next_id }),
    );
    let mut received = Vec::new();
    let (mut hover_text, mut errors, mut cancelled) = (String::new(), Vec::new(), None);
    while !(received.contains(&Received::Answer(hover.clone()))
        && received.contains(&Received::Published(Some(2))))
    {
        match client.receive() {
            Message::Response(r) => {
                if r.id == hover {
                    let value = &r.result.clone().unwrap()["contents"]["value"];
                    hover_text = value.as_str().unwrap().to_string();
                }
                if r.id == format {
                    cancelled = r.error.map(|e| e.code);
                }
                received.push(Received::Answer(r.id));
            }
            Message::Notification(n) if n.method == PublishDiagnostics::METHOD => {
                let p: PublishDiagnosticsParams = serde_json::from_value(n.params).unwrap();
                errors = p
                    .diagnostics
                    .iter()
                    .filter(|d| d.severity == Some(lsp_types::DiagnosticSeverity::ERROR))
                    .map(|d| d.range.start.line)
                    .collect();
                received.push(Received::Published(p.version));
            }
            _ => {}
        }
    }
    let at = |r: Received| received.iter().position(|x| *x == r).unwrap();
    let (outlined, format) = (at(Received::Answer(outlined)), at(Received::Answer(format)));
    let slow = at(Received::Answer(hover)).min(at(Received::Published(Some(2))));
    assert!(outlined < slow && format < slow, "{received:?}");
    assert_eq!(cancelled, Some(-32800), "the formatting is cancelled");
    assert_eq!(hover_text, "`#<depth>` = 1 here");
    // Version 1's analysis is not published again; version 2's error is.
    assert!(!received.contains(&Received::Published(Some(1))));
    assert_eq!(errors, [310], "{received:?}");
    client.stop();
}

/// LinuxCNC's scopes: in each `o… sub`, `#<depth>` is the sub's own;
/// `#<_last>` is global.
const SCOPES_PROGRAM: &str = "o<drill> sub\n#<hole> = #1\n#<depth> = #<hole>\nG1 Z-#<depth> F100\n\
    #<_last> = #<depth>\no<drill> endsub\no<mill> sub\n#<depth> = 2\n#<pass> = 1\n\
    G1 Z-#<depth> F100\no<mill> endsub\n#<depth> = 5\no<drill> call [#<depth>]\no<mill> call\n\
    G0 Z#<_last>\nM2\n";

#[test]
fn a_linuxcnc_subs_locals_are_its_own() {
    use lsp_types::request::{Completion, GotoDefinition, References, Rename};
    let mut client = Client::start();
    let doc = uri("/nowhere/scopes/part.ngc");
    client.open(&doc, SCOPES_PROGRAM);
    let none = serde_json::json!({});
    let lines = |answer: serde_json::Value| -> Vec<u64> {
        places(&answer).into_iter().map(|(_, line)| line).collect()
    };
    // `#<depth>` in o<drill>: renamed there only.
    let edit = client.ask(
        Rename::METHOD,
        &doc,
        (3, 7),
        serde_json::json!({ "newName": "cut" }),
    );
    let renamed: Vec<_> = edit["changes"][doc.as_str()]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["range"]["start"]["line"].as_u64().unwrap())
        .collect();
    assert_eq!(renamed, [2, 3, 4], "{edit}");
    // The main program's `#<depth>`: its own places.
    let context = serde_json::json!({ "context": { "includeDeclaration": true } });
    let refs = client.ask(References::METHOD, &doc, (11, 1), context);
    assert_eq!(lines(refs), [11, 12]);
    // o<mill>'s `#<depth>` is set in o<mill>; `#<_last>` in o<drill>.
    let def = client.ask(GotoDefinition::METHOD, &doc, (9, 7), none.clone());
    assert_eq!(lines(def), [7]);
    let def = client.ask(GotoDefinition::METHOD, &doc, (14, 5), none.clone());
    assert_eq!(lines(def), [4]);
    // Completion offers the names in scope at the cursor.
    let mut offered = |at| -> Vec<String> {
        let answer = client.ask(Completion::METHOD, &doc, at, none.clone());
        let names = answer.as_array().unwrap().iter();
        names
            .filter(|c| c["kind"] == 6)
            .map(|c| c["label"].as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(offered((9, 0)), ["#<_last>", "#<depth>", "#<pass>"]);
    assert_eq!(offered((15, 0)), ["#<_last>", "#<depth>"]);
    assert_eq!(offered((3, 0)), ["#<_last>", "#<depth>", "#<hole>"]);
    client.stop();
}

/// `ger lsp` run as an editor runs it, on stdio, with `env` set.
struct Stdio {
    child: std::process::Child,
    stdin: std::process::ChildStdin,
    stdout: std::io::BufReader<std::process::ChildStdout>,
}

impl Stdio {
    fn start(env: &[(&str, &std::path::Path)]) -> Stdio {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_ger"));
        command
            .arg("lsp")
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped());
        for (key, value) in env {
            command.env(key, value);
        }
        let mut child = command.spawn().unwrap();
        let stdin = child.stdin.take().unwrap();
        let stdout = std::io::BufReader::new(child.stdout.take().unwrap());
        let mut s = Stdio {
            child,
            stdin,
            stdout,
        };
        s.send(
            serde_json::json!({"jsonrpc": "2.0", "id": 0, "method": "initialize",
            "params": {"capabilities": {}, "processId": null, "rootUri": null}}),
        );
        assert_eq!(s.receive()["id"], 0);
        s.send(serde_json::json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}));
        s
    }

    fn send(&mut self, value: serde_json::Value) {
        use std::io::Write;
        let body = value.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
        self.stdin.flush().unwrap();
    }

    fn receive(&mut self) -> serde_json::Value {
        use std::io::{BufRead, Read};
        let mut length = 0;
        loop {
            let mut line = String::new();
            self.stdout.read_line(&mut line).unwrap();
            if line == "\r\n" {
                break;
            }
            if let Some(n) = line.strip_prefix("Content-Length: ") {
                length = n.trim().parse().unwrap();
            }
        }
        let mut body = vec![0; length];
        self.stdout.read_exact(&mut body).unwrap();
        serde_json::from_slice(&body).unwrap()
    }

    /// The answer to request `id`.
    fn answer(&mut self, id: i32) -> serde_json::Value {
        loop {
            let message = self.receive();
            if message["id"] == id {
                return message;
            }
        }
    }

    fn stop(mut self) {
        self.send(serde_json::json!({"jsonrpc": "2.0", "id": -1, "method": "shutdown"}));
        self.answer(-1);
        self.send(serde_json::json!({"jsonrpc": "2.0", "method": "exit"}));
        assert!(self.child.wait().unwrap().success());
    }
}

#[test]
fn definition_of_a_standard_library_wizard_is_a_file_the_editor_can_open() {
    let cache = tempfile::tempdir().unwrap();
    let mut server = Stdio::start(&[("XDG_CACHE_HOME", cache.path())]);
    let text = "G21 G90\nG0 X0 Y0 Z5\nF300\nPocket 20 10 2\nM30\n";
    server.send(
        serde_json::json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {
        "textDocument": {"uri": "file:///nowhere/std/part.egc", "languageId": "gcode",
                         "version": 1, "text": text}}}),
    );
    for id in [1, 2] {
        server.send(
            serde_json::json!({"jsonrpc": "2.0", "id": id, "method": "textDocument/definition",
            "params": {"textDocument": {"uri": "file:///nowhere/std/part.egc"},
                       "position": {"line": 3, "character": 2}}}),
        );
        let found = server.answer(id)["result"].clone();
        let uri = found[0]["uri"].as_str().unwrap().to_string();
        let path = std::path::PathBuf::from(uri.strip_prefix("file://").unwrap());
        assert_eq!(path, cache.path().join("ger/stdlib/Pocket.rhai"), "{found}");
        // The wizard as the binary has it: its manual is in the file.
        let written = std::fs::read_to_string(&path).unwrap();
        let stdlib = ger::wizard::standard_library();
        let pocket = stdlib.iter().find(|w| w.name == "Pocket").unwrap();
        assert_eq!(written, pocket.text);
        assert!(std::fs::metadata(&path).unwrap().permissions().readonly());
        // A stale copy (another ger's) is written again.
        if id == 1 {
            std::fs::remove_file(&path).unwrap();
            std::fs::write(&path, "// an older Pocket\n").unwrap();
        }
    }
    server.stop();
}
