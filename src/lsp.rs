//! `ger lsp`: the Language Server Protocol on a connection (stdio for an
//! editor, in memory for the tests), as rust-analyzer splits it: this
//! module is the protocol loop; [`analysis`] is the pure part (a
//! document's text in, its diagnostics and where the tool is after each
//! line out).
//!
//! Nothing that compiles or runs a program runs on the loop: a
//! document's analysis, the values a hover shows (a run of its own) and
//! formatting (two compiles) each run on a thread of their own and report
//! back, so the loop answers the editor at once from the last analysis
//! however long the program. A change cancels the work under way on the
//! older text (the compile stops at its next batch) and the newest text
//! is analysed next, never each keystroke in turn; a request that needs
//! work not done yet (the document's first analysis, the values) waits
//! for it without holding the loop; `$/cancelRequest` drops a waiting
//! request and stops its work.
//!
//! Architecture Invariant: calls the driver (through [`analysis`]) and
//! is called by no module of the library.

pub mod analysis;
pub mod answers;
pub mod codes;
pub mod format;
pub mod index;

use crate::diagnostic::Level;
use crate::driver::fs::{Disk, Memory};
use analysis::{Analysis, At};
use lsp_server::{Connection, Message, Notification, Request, RequestId, Response};
use lsp_types::notification::{
    Cancel, DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, Exit,
    Notification as _, PublishDiagnostics,
};
use lsp_types::request::{
    DocumentSymbolRequest, Formatting, HoverRequest, InlayHintRequest, Request as _, Shutdown,
};
use lsp_types::{
    Diagnostic, DiagnosticRelatedInformation, DiagnosticSeverity, InlayHint, InlayHintLabel,
    InlayHintParams, Location, OneOf, Position, PublishDiagnosticsParams, Range,
    ServerCapabilities, TextDocumentSyncCapability, TextDocumentSyncKind, Uri,
};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::PathBuf;
use std::str::FromStr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Sender;
use std::sync::Arc;

type Error = Box<dyn std::error::Error + Send + Sync>;

/// An open document: its text and its last analysis.
struct Document {
    text: String,
    version: i32,
    /// The last analysis, of the text it was made of: what requests are
    /// answered from while a newer one is under way.
    analysed: Option<Analysed>,
    /// The values of its variables where the analysed text reads and
    /// sets them.
    values: Values,
}

/// An analysis and the text it was made of.
struct Analysed {
    text: String,
    analysis: Analysis,
}

/// The values of a document's variables: a run of the program of its
/// own, started off the loop by the first hover that needs them.
enum Values {
    Unknown,
    /// Being worked out by the job numbered so, stopped by its flag.
    Working(u64, Arc<AtomicBool>),
    Known(HashMap<usize, crate::eval::Seen>),
}

/// What the loop waits for: a message from the editor, or work done off
/// the loop (`None`: cancelled).
enum Event {
    Message(Message),
    Analysed {
        uri: Uri,
        version: i32,
        text: String,
        analysis: Option<Box<Analysis>>,
    },
    /// The values of a document's analysed text, by the job numbered so.
    Values {
        uri: Uri,
        job: u64,
        values: Option<HashMap<usize, crate::eval::Seen>>,
    },
    /// A formatting request's answer for the text of `version`.
    Formatted {
        id: RequestId,
        version: i32,
        text: String,
        result: Option<Result<String, String>>,
    },
}

/// The server's state: the open documents and the work under way.
struct Server<'c> {
    connection: &'c Connection,
    documents: BTreeMap<Uri, Document>,
    /// Documents changed since their last analysis began.
    stale: BTreeSet<Uri>,
    /// The analyses under way, each with its cancel flag.
    running: BTreeMap<Uri, Arc<AtomicBool>>,
    /// Requests that wait for work under way (their document's first
    /// analysis, its values), asked again when it is done.
    waiting: Vec<Request>,
    /// The formatting under way, by request: its document and cancel flag.
    formatting: HashMap<RequestId, (Uri, Arc<AtomicBool>)>,
    /// The number of the last job started for values.
    jobs: u64,
    /// Where work done off the loop reports.
    events: Sender<Event>,
}

/// What `ger lsp` offers.
fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        inlay_hint_provider: Some(OneOf::Left(true)),
        hover_provider: Some(lsp_types::HoverProviderCapability::Simple(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        document_formatting_provider: Some(OneOf::Left(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Left(true)),
        completion_provider: Some(lsp_types::CompletionOptions {
            trigger_characters: Some(vec!["#".into(), "<".into()]),
            ..lsp_types::CompletionOptions::default()
        }),
        signature_help_provider: Some(lsp_types::SignatureHelpOptions {
            trigger_characters: Some(vec![" ".into(), "(".into(), ",".into()]),
            ..lsp_types::SignatureHelpOptions::default()
        }),
        ..ServerCapabilities::default()
    }
}

/// Serve `connection` until the client shuts it down.
pub fn serve(connection: &Connection) -> Result<(), Error> {
    connection.initialize(serde_json::to_value(capabilities())?)?;
    let (events, received) = std::sync::mpsc::channel();
    // The editor's messages join the work's reports in one queue.
    let (from_editor, to_loop) = (connection.receiver.clone(), events.clone());
    std::thread::spawn(move || {
        for message in from_editor {
            if to_loop.send(Event::Message(message)).is_err() {
                break;
            }
        }
    });
    let mut server = Server {
        connection,
        documents: BTreeMap::new(),
        stale: BTreeSet::new(),
        running: BTreeMap::new(),
        waiting: Vec::new(),
        formatting: HashMap::new(),
        jobs: 0,
        events,
    };
    let mut shut_down = false;
    while let Ok(event) = received.recv() {
        match event {
            Event::Message(Message::Request(request)) if request.method == Shutdown::METHOD => {
                shut_down = true;
                server.send(Response::new_ok(request.id, ()))?;
            }
            Event::Message(Message::Request(request)) => server.ask(request)?,
            Event::Message(Message::Notification(n)) if n.method == Exit::METHOD => {
                return match shut_down {
                    true => Ok(()),
                    false => Err("exit before shutdown".into()),
                };
            }
            Event::Message(Message::Notification(notification)) => server.note(notification)?,
            Event::Message(Message::Response(_)) => {}
            Event::Analysed {
                uri,
                version,
                text,
                analysis,
            } => server.analysed(uri, version, text, analysis)?,
            Event::Values { uri, job, values } => server.valued(uri, job, values)?,
            Event::Formatted {
                id,
                version,
                text,
                result,
            } => server.formatted(id, version, &text, result)?,
        }
        server.start_stale();
    }
    Ok(())
}

impl Server<'_> {
    fn send(&self, response: Response) -> Result<(), Error> {
        self.connection.sender.send(Message::Response(response))?;
        Ok(())
    }

    /// Answer `request` now, or once the work it waits for is done.
    fn ask(&mut self, request: Request) -> Result<(), Error> {
        match self.answer(request) {
            Some(response) => self.send(response),
            None => Ok(()),
        }
    }

    /// Ask again the requests about `uri` that wait.
    fn ask_again(&mut self, uri: &Uri) -> Result<(), Error> {
        let (again, still): (Vec<_>, Vec<_>) = std::mem::take(&mut self.waiting)
            .into_iter()
            .partition(|r| uri_in(r).as_ref() == Some(uri));
        self.waiting = still;
        again.into_iter().try_for_each(|r| self.ask(r))
    }

    /// A document opened, changed or closed; a request cancelled.
    fn note(&mut self, notification: Notification) -> Result<(), Error> {
        let params = notification.params;
        match notification.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(params)
                else {
                    return Ok(());
                };
                let document = Document {
                    text: p.text_document.text,
                    version: p.text_document.version,
                    analysed: None,
                    values: Values::Unknown,
                };
                self.documents.insert(p.text_document.uri.clone(), document);
                self.stale.insert(p.text_document.uri);
            }
            DidChangeTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(params)
                else {
                    return Ok(());
                };
                let uri = p.text_document.uri;
                let (Some(document), Some(change)) = (
                    self.documents.get_mut(&uri),
                    p.content_changes.into_iter().last(),
                ) else {
                    return Ok(());
                };
                document.text = change.text;
                document.version = p.text_document.version;
                // The work under way is of older text.
                self.cancel_work(&uri);
                self.stale.insert(uri);
            }
            DidCloseTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(params)
                {
                    let uri = &p.text_document.uri;
                    self.cancel_work(uri);
                    self.documents.remove(uri);
                    self.stale.remove(uri);
                    self.ask_again(uri)?;
                }
            }
            Cancel::METHOD => {
                if let Ok(p) = serde_json::from_value::<lsp_types::CancelParams>(params) {
                    self.cancel_request(match p.id {
                        lsp_types::NumberOrString::Number(n) => n.into(),
                        lsp_types::NumberOrString::String(s) => s.into(),
                    })?;
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// Stop the analysis and formatting under way for `uri`.
    fn cancel_work(&self, uri: &Uri) {
        let formatting = self.formatting.values().filter(|(u, _)| u == uri);
        for cancel in self
            .running
            .get(uri)
            .into_iter()
            .chain(formatting.map(|(_, c)| c))
        {
            cancel.store(true, Ordering::Relaxed);
        }
    }

    /// The editor no longer wants the answer to `id`: its work is
    /// stopped, and it is answered so.
    fn cancel_request(&mut self, id: RequestId) -> Result<(), Error> {
        let waited = self.waiting.iter().position(|r| r.id == id);
        let waited = waited.map(|at| self.waiting.remove(at)).is_some();
        let formatted = self.formatting.remove(&id);
        if let Some((_, cancel)) = &formatted {
            cancel.store(true, Ordering::Relaxed);
        }
        if !waited && formatted.is_none() {
            return Ok(());
        }
        let code = lsp_server::ErrorCode::RequestCanceled as i32;
        self.send(Response::new_err(id, code, "cancelled".into()))
    }

    /// Start analysing each changed document that is not being analysed
    /// (with every open one over the disk), on a thread of its own.
    fn start_stale(&mut self) {
        let ready: Vec<Uri> = self
            .stale
            .iter()
            .filter(|uri| !self.running.contains_key(*uri))
            .cloned()
            .collect();
        for uri in ready {
            self.stale.remove(&uri);
            let (Some(path), Some(document)) = (path_of(&uri), self.documents.get(&uri)) else {
                continue;
            };
            let cancel = Arc::new(AtomicBool::new(false));
            self.running.insert(uri.clone(), Arc::clone(&cancel));
            let open = self.open_texts();
            let (text, version, events) =
                (document.text.clone(), document.version, self.events.clone());
            std::thread::spawn(move || {
                let fs = over_disk(open);
                let analysis = analysis::analyse_unless(&fs, &path, &text, &cancel).map(Box::new);
                let _ = events.send(Event::Analysed {
                    uri,
                    version,
                    text,
                    analysis,
                });
            });
        }
    }

    /// An analysis is done: kept, its diagnostics published and the
    /// requests that waited for it answered, unless it was cancelled or
    /// the document changed since it began.
    fn analysed(
        &mut self,
        uri: Uri,
        version: i32,
        text: String,
        analysis: Option<Box<Analysis>>,
    ) -> Result<(), Error> {
        self.running.remove(&uri);
        let (Some(document), Some(analysis)) = (self.documents.get_mut(&uri), analysis) else {
            return Ok(());
        };
        if document.version != version || self.stale.contains(&uri) {
            return Ok(());
        }
        let params = PublishDiagnosticsParams {
            uri: uri.clone(),
            diagnostics: analysis
                .diagnostics
                .iter()
                .map(|d| to_lsp(&uri, d))
                .collect(),
            version: Some(version),
        };
        let analysis = *analysis;
        document.analysed = Some(Analysed { text, analysis });
        // The values were of the text analysed before.
        if let Values::Working(_, cancel) = &document.values {
            cancel.store(true, Ordering::Relaxed);
        }
        document.values = Values::Unknown;
        let notification = Notification::new(PublishDiagnostics::METHOD.into(), params);
        self.connection
            .sender
            .send(Message::Notification(notification))?;
        self.ask_again(&uri)
    }

    /// A document's values are worked out: kept, and the hovers that
    /// waited for them answered, unless a newer analysis replaced the
    /// text they are of (it started a job of its own).
    fn valued(
        &mut self,
        uri: Uri,
        job: u64,
        values: Option<HashMap<usize, crate::eval::Seen>>,
    ) -> Result<(), Error> {
        let Some(document) = self.documents.get_mut(&uri) else {
            return Ok(());
        };
        if !matches!(document.values, Values::Working(j, _) if j == job) {
            return Ok(());
        }
        document.values = match values {
            Some(values) => Values::Known(values),
            None => Values::Unknown,
        };
        self.ask_again(&uri)
    }

    /// A formatting is done: its answer, unless the editor cancelled the
    /// request (answered then) or changed the document since.
    fn formatted(
        &mut self,
        id: RequestId,
        version: i32,
        text: &str,
        result: Option<Result<String, String>>,
    ) -> Result<(), Error> {
        let Some((uri, _)) = self.formatting.remove(&id) else {
            return Ok(());
        };
        let current = self
            .documents
            .get(&uri)
            .is_some_and(|d| d.version == version);
        let response = match result {
            Some(Ok(formatted)) if current => {
                let edits = match formatted == text {
                    true => Vec::new(),
                    false => vec![lsp_types::TextEdit {
                        range: Range::new(
                            Position::new(0, 0),
                            Position::new(text.split('\n').count() as u32, 0),
                        ),
                        new_text: formatted,
                    }],
                };
                Response::new_ok(id, edits)
            }
            Some(Err(why)) if current => {
                Response::new_err(id, lsp_server::ErrorCode::RequestFailed as i32, why)
            }
            _ => Response::new_err(
                id,
                lsp_server::ErrorCode::ContentModified as i32,
                "the document changed while it was being formatted".into(),
            ),
        };
        self.send(response)
    }

    /// The open documents' texts, by path.
    fn open_texts(&self) -> Vec<(PathBuf, String)> {
        self.documents
            .iter()
            .filter_map(|(uri, d)| Some((path_of(uri)?, d.text.clone())))
            .collect()
    }

    /// The answer to a request; `None`: it waits for work under way (its
    /// document's first analysis, a formatting, the values a hover
    /// shows), answered when that is done.
    fn answer(&mut self, request: Request) -> Option<Response> {
        let uri = uri_in(&request);
        let analysing = |uri: &Uri| self.stale.contains(uri) || self.running.contains_key(uri);
        let unanalysed = uri.as_ref().is_some_and(|uri| {
            analysing(uri)
                && self
                    .documents
                    .get(uri)
                    .is_some_and(|d| d.analysed.is_none())
        });
        if request.method == Formatting::METHOD {
            return self.format(request);
        }
        if unanalysed || self.wait_for_values(&request) {
            self.waiting.push(request);
            return None;
        }
        if let Some(response) = self.answer_at_place(&request) {
            return Some(response);
        }
        Some(match request.method.as_str() {
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
            _ => Response::new_err(
                request.id,
                lsp_server::ErrorCode::MethodNotFound as i32,
                format!("ger lsp does not answer {}", request.method),
            ),
        })
    }

    /// Start formatting the document, off the loop (it compiles the
    /// program twice), as one edit of its whole text; the `N` words
    /// renumbered unless the option `gerNumbers` says `remove` or `keep`.
    /// `Some`: answered at once.
    fn format(&mut self, request: Request) -> Option<Response> {
        use format::Numbers;
        let p = match serde_json::from_value::<lsp_types::DocumentFormattingParams>(request.params)
        {
            Ok(p) => p,
            Err(e) => {
                let code = lsp_server::ErrorCode::InvalidParams as i32;
                return Some(Response::new_err(request.id, code, e.to_string()));
            }
        };
        let uri = p.text_document.uri;
        let (Some(document), Some(path)) = (self.documents.get(&uri), path_of(&uri)) else {
            return Some(Response::new_ok(request.id, serde_json::Value::Null));
        };
        let numbers = match p.options.properties.get("gerNumbers") {
            Some(lsp_types::FormattingProperty::String(s)) if s == "remove" => Numbers::Remove,
            Some(lsp_types::FormattingProperty::String(s)) if s == "keep" => Numbers::Keep,
            _ => Numbers::Renumber,
        };
        let cancel = Arc::new(AtomicBool::new(false));
        let (id, open, events) = (request.id, self.open_texts(), self.events.clone());
        let (text, version) = (document.text.clone(), document.version);
        self.formatting
            .insert(id.clone(), (uri, Arc::clone(&cancel)));
        std::thread::spawn(move || {
            let fs = over_disk(open);
            let result = analysis::formatted_unless(&fs, &path, &text, numbers, &cancel);
            let _ = events.send(Event::Formatted {
                id,
                version,
                text,
                result,
            });
        });
        None
    }

    /// The document's outline: subprograms, calls, loops, tool changes.
    #[allow(deprecated)] // `DocumentSymbol::deprecated`, which LSP keeps
    fn symbols(&self, uri: &Uri) -> Vec<lsp_types::DocumentSymbol> {
        use analysis::OutlineKind;
        let Some(Analysed { analysis, .. }) =
            self.documents.get(uri).and_then(|d| d.analysed.as_ref())
        else {
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

    /// The answer to a request about a place in a document (hover,
    /// definition, references, rename, completion, signature help);
    /// `None`: not such a request.
    fn answer_at_place(&self, request: &Request) -> Option<Response> {
        use lsp_types::request::{
            Completion, GotoDefinition, References, Rename, SignatureHelpRequest,
        };
        let method = request.method.as_str();
        let known = [
            HoverRequest::METHOD,
            GotoDefinition::METHOD,
            References::METHOD,
            Rename::METHOD,
            Completion::METHOD,
            SignatureHelpRequest::METHOD,
        ];
        if !known.contains(&method) {
            return None;
        }
        let id = request.id.clone();
        let Ok(place) =
            serde_json::from_value::<lsp_types::TextDocumentPositionParams>(request.params.clone())
        else {
            let message = format!("{method}: no text document and position");
            let code = lsp_server::ErrorCode::InvalidParams as i32;
            return Some(Response::new_err(id, code, message));
        };
        let uri = place.text_document.uri;
        let at = At {
            line: place.position.line,
            column: place.position.character,
        };
        let Some(document) = self.documents.get(&uri) else {
            return Some(Response::new_ok(id, serde_json::Value::Null));
        };
        let Some(Analysed { text, analysis }) = &document.analysed else {
            return Some(Response::new_ok(id, serde_json::Value::Null));
        };
        let asked = answers::Document::new(text, analysis);
        let at_uri = |t: answers::Target| {
            let uri = match &t.file {
                Some(path) => uri_of(path)?,
                None => uri.clone(),
            };
            Some(Location::new(
                uri,
                Range::new(position(t.from), position(t.to)),
            ))
        };
        Some(match method {
            HoverRequest::METHOD => {
                let hover = asked
                    .hover(
                        at,
                        match &document.values {
                            Values::Known(values) => Some(values),
                            _ => None,
                        },
                    )
                    .map(|text| lsp_types::Hover {
                        contents: lsp_types::HoverContents::Markup(lsp_types::MarkupContent {
                            kind: lsp_types::MarkupKind::Markdown,
                            value: text,
                        }),
                        range: None,
                    });
                Response::new_ok(id, hover)
            }
            GotoDefinition::METHOD => {
                let mut found: Vec<_> = asked
                    .definition(at)
                    .into_iter()
                    .filter_map(at_uri)
                    .collect();
                let stdlib = asked.stdlib_wizard_at(at).and_then(stdlib_copy);
                found.extend(stdlib.as_deref().and_then(uri_of).map(|uri| {
                    Location::new(uri, Range::new(Position::new(0, 0), Position::new(0, 0)))
                }));
                Response::new_ok(id, found)
            }
            References::METHOD => {
                let found: Vec<_> = asked
                    .references(at)
                    .into_iter()
                    .filter_map(at_uri)
                    .collect();
                Response::new_ok(id, found)
            }
            Rename::METHOD => {
                let new = request.params["newName"].as_str().unwrap_or_default();
                match asked.rename(at, new) {
                    Ok(edits) => Response::new_ok(id, rename_edit(&uri, edits)),
                    Err(why) => {
                        Response::new_err(id, lsp_server::ErrorCode::InvalidParams as i32, why)
                    }
                }
            }
            Completion::METHOD => Response::new_ok(id, completions(asked.completion(at))),
            _ => Response::new_ok(id, asked.signature(at).map(signature_help)),
        })
    }

    /// Whether `request` is a hover on a variable whose values are not
    /// known yet: they are then worked out off the loop (a run of the
    /// analysed text), and the hover waits for them.
    fn wait_for_values(&mut self, request: &Request) -> bool {
        if request.method != HoverRequest::METHOD {
            return false;
        }
        let Ok(place) =
            serde_json::from_value::<lsp_types::TextDocumentPositionParams>(request.params.clone())
        else {
            return false;
        };
        let uri = place.text_document.uri;
        let at = At {
            line: place.position.line,
            column: place.position.character,
        };
        let open = self.open_texts();
        let (Some(path), Some(document)) = (path_of(&uri), self.documents.get_mut(&uri)) else {
            return false;
        };
        let Some(Analysed { text, analysis }) = &document.analysed else {
            return false;
        };
        if answers::Document::new(text, analysis).var_at(at).is_none() {
            return false;
        }
        match document.values {
            Values::Known(_) => return false,
            Values::Working(..) => return true,
            Values::Unknown => {}
        }
        self.jobs += 1;
        let (job, cancel) = (self.jobs, Arc::new(AtomicBool::new(false)));
        document.values = Values::Working(job, Arc::clone(&cancel));
        let (text, events) = (text.clone(), self.events.clone());
        std::thread::spawn(move || {
            let fs = over_disk(open);
            let values = analysis::watch_unless(&fs, &path, &text, &cancel);
            let _ = events.send(Event::Values { uri, job, values });
        });
        true
    }

    /// The tool's place and time after each moving line in the range.
    fn hints(&self, p: &InlayHintParams) -> Vec<InlayHint> {
        let Some(Analysed { analysis, .. }) = self
            .documents
            .get(&p.text_document.uri)
            .and_then(|d| d.analysed.as_ref())
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

/// A copy of the standard library's wizard `name` (compiled into the
/// binary) in the cache folder (`$XDG_CACHE_HOME/ger/stdlib`, else
/// `~/.cache/ger/stdlib`, else the temporary folder's `ger-stdlib`), for
/// the editor to open on go to definition: written when missing or not
/// this binary's, read-only (editing it changes no wizard; a wizard of
/// that name in a `wizards/` folder does). `None`: it cannot be written.
fn stdlib_copy(name: &str) -> Option<PathBuf> {
    let source = crate::wizard::standard_library()
        .into_iter()
        .find(|w| w.name == name)?;
    let env = |key| {
        std::env::var_os(key)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    let folder = match (env("XDG_CACHE_HOME"), env("HOME")) {
        (Some(cache), _) => cache.join("ger/stdlib"),
        (None, Some(home)) => home.join(".cache/ger/stdlib"),
        (None, None) => std::env::temp_dir().join("ger-stdlib"),
    };
    let path = folder.join(format!("{name}.rhai"));
    if std::fs::read_to_string(&path).is_ok_and(|t| t == source.text) {
        return Some(path);
    }
    std::fs::create_dir_all(&folder).ok()?;
    // Written aside and renamed: another server may be reading it.
    let aside = tempfile::NamedTempFile::new_in(&folder).ok()?;
    std::fs::write(aside.path(), &source.text).ok()?;
    let mut read_only = std::fs::metadata(aside.path()).ok()?.permissions();
    read_only.set_readonly(true);
    std::fs::set_permissions(aside.path(), read_only).ok()?;
    aside.persist(&path).ok()?;
    Some(path)
}

/// The document a request is about.
fn uri_in(request: &Request) -> Option<Uri> {
    let uri = request.params.get("textDocument")?.get("uri")?.as_str()?;
    Uri::from_str(uri).ok()
}

/// The open documents' texts over the disk.
fn over_disk(open: Vec<(PathBuf, String)>) -> Memory<'static> {
    let mut fs = Memory::over(&Disk);
    for (path, text) in open {
        fs.insert(path, text);
    }
    fs
}

fn position(at: At) -> Position {
    Position::new(at.line, at.column)
}

/// Rename's edits as LSP has them.
fn rename_edit(uri: &Uri, edits: Vec<(answers::Target, String)>) -> lsp_types::WorkspaceEdit {
    let edits = edits
        .into_iter()
        .map(|(t, new_text)| lsp_types::TextEdit {
            range: Range::new(position(t.from), position(t.to)),
            new_text,
        })
        .collect();
    lsp_types::WorkspaceEdit {
        changes: Some(std::collections::HashMap::from([(uri.clone(), edits)])),
        ..lsp_types::WorkspaceEdit::default()
    }
}

/// Completions as LSP has them.
fn completions(offered: Vec<answers::Completion>) -> Vec<lsp_types::CompletionItem> {
    use answers::CompletionKind as K;
    offered
        .into_iter()
        .map(|c| lsp_types::CompletionItem {
            kind: Some(match c.kind {
                K::Code => lsp_types::CompletionItemKind::KEYWORD,
                K::Variable => lsp_types::CompletionItemKind::VARIABLE,
                K::Wizard => lsp_types::CompletionItemKind::FUNCTION,
            }),
            detail: Some(c.detail),
            insert_text_format: c
                .snippet
                .as_ref()
                .map(|_| lsp_types::InsertTextFormat::SNIPPET),
            insert_text: c.snippet,
            label: c.label,
            ..lsp_types::CompletionItem::default()
        })
        .collect()
}

/// Signature help as LSP has it.
fn signature_help(s: answers::Signature) -> lsp_types::SignatureHelp {
    let parameters = s
        .parameters
        .into_iter()
        .map(|p| lsp_types::ParameterInformation {
            label: lsp_types::ParameterLabel::Simple(p),
            documentation: None,
        })
        .collect();
    lsp_types::SignatureHelp {
        signatures: vec![lsp_types::SignatureInformation {
            label: s.label,
            documentation: Some(lsp_types::Documentation::String(s.doc)),
            parameters: Some(parameters),
            active_parameter: Some(s.active as u32),
        }],
        active_signature: Some(0),
        active_parameter: Some(s.active as u32),
    }
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
