//! `ger lsp`: the Language Server Protocol on a connection (stdio for an
//! editor, in memory for the tests), as rust-analyzer splits it: this
//! module is the protocol loop; [`analysis`] is the pure part (a
//! document's text in, its diagnostics and where the tool is after each
//! line out).
//!
//! Every change is coalesced with the ones already waiting before a
//! document is analysed again: an editor typing fast on a long program is
//! answered for its newest text, never for each keystroke in turn.
//!
//! Architecture Invariant: calls the driver (through [`analysis`]) and
//! is called by no module of the library.

pub mod analysis;
pub mod codes;

use crate::diagnostic::Level;
use crate::driver::fs::{Disk, Memory};
use analysis::{analyse, Analysis, At};
use lsp_server::{Connection, Message, Notification, Request, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, Notification as _,
    PublishDiagnostics,
};
use lsp_types::request::{DocumentSymbolRequest, HoverRequest, InlayHintRequest, Request as _};
use lsp_types::{
    Diagnostic, DiagnosticRelatedInformation, DiagnosticSeverity, InlayHint, InlayHintLabel,
    InlayHintParams, Location, OneOf, Position, PublishDiagnosticsParams, Range,
    ServerCapabilities, TextDocumentSyncCapability, TextDocumentSyncKind, Uri,
};
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::str::FromStr;

type Error = Box<dyn std::error::Error + Send + Sync>;

/// An open document: its text and its last analysis.
struct Document {
    text: String,
    version: i32,
    analysis: Option<Analysis>,
}

/// The server's state: the open documents.
#[derive(Default)]
struct Server {
    documents: BTreeMap<Uri, Document>,
    /// Documents changed since their last analysis.
    stale: BTreeSet<Uri>,
}

/// Serve `connection` until the client shuts it down.
pub fn serve(connection: &Connection) -> Result<(), Error> {
    let capabilities = ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        inlay_hint_provider: Some(OneOf::Left(true)),
        hover_provider: Some(lsp_types::HoverProviderCapability::Simple(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        ..ServerCapabilities::default()
    };
    connection.initialize(serde_json::to_value(capabilities)?)?;
    let mut server = Server::default();
    while let Ok(message) = connection.receiver.recv() {
        let mut batch = vec![message];
        // What is already waiting is read before anything is analysed.
        batch.extend(connection.receiver.try_iter());
        for message in batch {
            match message {
                Message::Request(request) => {
                    if connection.handle_shutdown(&request)? {
                        return Ok(());
                    }
                    server.analyse_stale(connection)?;
                    let response = server.answer(request);
                    connection.sender.send(Message::Response(response))?;
                }
                Message::Notification(notification) => server.note(notification),
                Message::Response(_) => {}
            }
        }
        server.analyse_stale(connection)?;
    }
    Ok(())
}

impl Server {
    /// A document opened, changed or closed.
    fn note(&mut self, notification: Notification) {
        match notification.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(
                    notification.params,
                ) else {
                    return;
                };
                let document = Document {
                    text: p.text_document.text,
                    version: p.text_document.version,
                    analysis: None,
                };
                self.documents.insert(p.text_document.uri.clone(), document);
                self.stale.insert(p.text_document.uri);
            }
            DidChangeTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(
                    notification.params,
                ) else {
                    return;
                };
                let uri = p.text_document.uri;
                let (Some(document), Some(change)) = (
                    self.documents.get_mut(&uri),
                    p.content_changes.into_iter().last(),
                ) else {
                    return;
                };
                document.text = change.text;
                document.version = p.text_document.version;
                self.stale.insert(uri);
            }
            DidCloseTextDocument::METHOD => {
                if let Ok(p) = serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(
                    notification.params,
                ) {
                    self.documents.remove(&p.text_document.uri);
                    self.stale.remove(&p.text_document.uri);
                }
            }
            _ => {}
        }
    }

    /// Analyse every changed document (with every open one over the disk)
    /// and publish its diagnostics.
    fn analyse_stale(&mut self, connection: &Connection) -> Result<(), Error> {
        if self.stale.is_empty() {
            return Ok(());
        }
        let mut open = Memory::over(&Disk);
        for (uri, document) in &self.documents {
            if let Some(path) = path_of(uri) {
                open.insert(path, document.text.clone());
            }
        }
        for uri in std::mem::take(&mut self.stale) {
            let (Some(path), Some(document)) = (path_of(&uri), self.documents.get(&uri)) else {
                continue;
            };
            let analysis = analyse(&open, &path, &document.text);
            let params = PublishDiagnosticsParams {
                uri: uri.clone(),
                diagnostics: analysis
                    .diagnostics
                    .iter()
                    .map(|d| to_lsp(&uri, d))
                    .collect(),
                version: Some(document.version),
            };
            let notification = Notification::new(PublishDiagnostics::METHOD.into(), params);
            connection
                .sender
                .send(Message::Notification(notification))?;
            if let Some(document) = self.documents.get_mut(&uri) {
                document.analysis = Some(analysis);
            }
        }
        Ok(())
    }

    /// The answer to a request.
    fn answer(&self, request: Request) -> Response {
        match request.method.as_str() {
            InlayHintRequest::METHOD => {
                let hints = serde_json::from_value::<InlayHintParams>(request.params)
                    .ok()
                    .map(|p| self.hints(&p))
                    .unwrap_or_default();
                Response::new_ok(request.id, hints)
            }
            DocumentSymbolRequest::METHOD => {
                let symbols =
                    serde_json::from_value::<lsp_types::DocumentSymbolParams>(request.params)
                        .ok()
                        .map(|p| self.symbols(&p.text_document.uri))
                        .unwrap_or_default();
                Response::new_ok(request.id, symbols)
            }
            HoverRequest::METHOD => {
                let hover = serde_json::from_value::<lsp_types::HoverParams>(request.params)
                    .ok()
                    .and_then(|p| self.hover(&p));
                Response::new_ok(request.id, hover)
            }
            _ => Response::new_err(
                request.id,
                lsp_server::ErrorCode::MethodNotFound as i32,
                format!("ger lsp does not answer {}", request.method),
            ),
        }
    }

    /// The document's outline: subprograms, calls, loops, tool changes.
    #[allow(deprecated)] // `DocumentSymbol::deprecated`, which LSP keeps
    fn symbols(&self, uri: &Uri) -> Vec<lsp_types::DocumentSymbol> {
        use analysis::OutlineKind;
        let Some(analysis) = self.documents.get(uri).and_then(|d| d.analysis.as_ref()) else {
            return Vec::new();
        };
        analysis
            .outline
            .iter()
            .map(|o| {
                let range = Range::new(position(o.from), position(o.to));
                lsp_types::DocumentSymbol {
                    name: o.name.clone(),
                    detail: None,
                    kind: match o.kind {
                        OutlineKind::Subprogram => lsp_types::SymbolKind::FUNCTION,
                        OutlineKind::Call => lsp_types::SymbolKind::METHOD,
                        OutlineKind::Loop => lsp_types::SymbolKind::NAMESPACE,
                        OutlineKind::ToolChange => lsp_types::SymbolKind::EVENT,
                    },
                    tags: None,
                    deprecated: None,
                    range,
                    selection_range: range,
                    children: None,
                }
            })
            .collect()
    }

    /// The meaning of the code under the cursor.
    fn hover(&self, p: &lsp_types::HoverParams) -> Option<lsp_types::Hover> {
        let place = &p.text_document_position_params;
        let document = self.documents.get(&place.text_document.uri)?;
        let at = At {
            line: place.position.line,
            column: place.position.character,
        };
        let text = analysis::hover(&document.text, at)?;
        Some(lsp_types::Hover {
            contents: lsp_types::HoverContents::Markup(lsp_types::MarkupContent {
                kind: lsp_types::MarkupKind::Markdown,
                value: text,
            }),
            range: None,
        })
    }

    /// The tool's place and time after each moving line in the range.
    fn hints(&self, p: &InlayHintParams) -> Vec<InlayHint> {
        let Some(analysis) = self
            .documents
            .get(&p.text_document.uri)
            .and_then(|d| d.analysis.as_ref())
        else {
            return Vec::new();
        };
        analysis
            .tool_at
            .iter()
            .filter(|h| (p.range.start.line..=p.range.end.line).contains(&h.at.line))
            .map(|h| InlayHint {
                position: position(h.at),
                label: InlayHintLabel::String(h.label.clone()),
                kind: None,
                text_edits: None,
                tooltip: None,
                padding_left: Some(true),
                padding_right: None,
                data: None,
            })
            .collect()
    }
}

fn position(at: At) -> Position {
    Position::new(at.line, at.column)
}

/// A diagnostic as LSP has it.
fn to_lsp(uri: &Uri, d: &analysis::Found) -> Diagnostic {
    let related = d
        .related
        .iter()
        .map(|(from, to, label)| DiagnosticRelatedInformation {
            location: Location::new(uri.clone(), Range::new(position(*from), position(*to))),
            message: label.clone(),
        })
        .collect::<Vec<_>>();
    Diagnostic {
        range: Range::new(position(d.from), position(d.to)),
        severity: Some(match d.level {
            Level::Error => DiagnosticSeverity::ERROR,
            Level::Warning => DiagnosticSeverity::WARNING,
            Level::Note => DiagnosticSeverity::INFORMATION,
        }),
        source: Some("ger".into()),
        message: d.message.clone(),
        related_information: (!related.is_empty()).then_some(related),
        ..Diagnostic::default()
    }
}

/// The file a `file:` URI names (`%xx` decoded).
fn path_of(uri: &Uri) -> Option<PathBuf> {
    let rest = uri.as_str().strip_prefix("file://")?;
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (
            bytes[i],
            bytes.get(i + 1).copied().and_then(hex),
            bytes.get(i + 2).copied().and_then(hex),
        ) {
            (b'%', Some(hi), Some(lo)) => {
                out.push((hi * 16 + lo) as u8);
                i += 3;
            }
            (b, _, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(out).ok().map(PathBuf::from)
}

/// The `file:` URI of a path (for the tests and clients).
pub fn uri_of(path: &std::path::Path) -> Option<Uri> {
    let mut text = String::from("file://");
    for b in path.to_string_lossy().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => {
                text.push(b as char)
            }
            _ => text.push_str(&format!("%{b:02X}")),
        }
    }
    Uri::from_str(&text).ok()
}
