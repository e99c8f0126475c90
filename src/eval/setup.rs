//! Setup directives (SPEC §3): `SetUnits`, `SetMargin`, `SetPart`,
//! `SetZero`, `SetTool`, `SetOffset`. They fill one machine model,
//! [`ir::Setup`]; defining the same thing twice is an error that shows both.

use super::value::Value;
use crate::ast::Names;
use crate::diagnostic::{error, Diagnostic, DiagnosticExt};
use crate::ir::{self, Tool, ToolShape, Units};
use crate::source::Span;
use std::collections::HashMap;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Directive {
    Units,
    Margin,
    Part,
    Zero,
    Tool,
    Offset,
}

impl Directive {
    pub const NAMES: [&'static str; 6] = [
        "SetUnits",
        "SetMargin",
        "SetPart",
        "SetZero",
        "SetTool",
        "SetOffset",
    ];
    const ALL: [Directive; 6] = [
        Directive::Units,
        Directive::Margin,
        Directive::Part,
        Directive::Zero,
        Directive::Tool,
        Directive::Offset,
    ];

    pub fn from_name(name: &str) -> Option<Directive> {
        Directive::NAMES
            .iter()
            .position(|n| n.eq_ignore_ascii_case(name))
            .map(|i| Directive::ALL[i])
    }

    fn signature(self) -> &'static str {
        match self {
            Directive::Units => "SetUnits \"inch\"|\"mm\"",
            Directive::Margin => "SetMargin margin",
            Directive::Part => "SetPart x y z",
            Directive::Zero => "SetZero x y z",
            Directive::Tool => {
                "SetTool number diameter [length] [\"flat\"|\"ball\"|\"drill\"|\"vee\"]"
            }
            Directive::Offset => "SetOffset 55..59 x y z",
        }
    }
}

/// The default tool when the table has no entry 1: a 1/4 in flat end mill.
const DEFAULT_TOOL_DIAMETER_INCH: f64 = 0.25;

#[derive(Default)]
pub struct SetupBuilder {
    setup: ir::Setup,
    /// Where each thing was defined, for "defined twice".
    defined: HashMap<(Directive, u32), Span>,
}

impl SetupBuilder {
    /// The setup as defined so far.
    pub fn get(&self) -> &ir::Setup {
        &self.setup
    }

    /// Diameter of a tool in the program's current units (for wizards).
    pub fn tool_diameter(&self, tool: u32, program_units: Option<Units>) -> f64 {
        let table_units = self.setup.units.or(program_units).unwrap_or(Units::Inch);
        let to = program_units.unwrap_or(table_units);
        match self.setup.tools.get(&tool) {
            Some(t) => t.diameter * table_units.factor(to),
            None => DEFAULT_TOOL_DIAMETER_INCH * Units::Inch.factor(to),
        }
    }

    pub fn apply(
        &mut self,
        directive: Directive,
        args: &[Value],
        span: Span,
        arg_spans: &[Span],
        names: &Names,
    ) -> Result<(), Diagnostic> {
        let arity_error = |wanted: &str| {
            error(
                format!(
                    "wrong arguments for {}",
                    Directive::NAMES[directive as usize]
                ),
                arg_spans
                    .first()
                    .map_or(span, |first| first.to(*arg_spans.last().unwrap_or(first))),
                format!("{wanted}, {} given", args.len()),
            )
            .with_note(format!("usage: {}", directive.signature()))
        };
        let number = |i: usize| -> Result<f64, Diagnostic> {
            match args[i] {
                Value::Number(n) if !ir::is_length(n) => Err(super::out_of_range(
                    "out of range".into(),
                    "numbers here",
                    n,
                    arg_spans[i],
                )),
                Value::Number(n) => Ok(n),
                other => Err(error(
                    "expected a number",
                    arg_spans[i],
                    format!("this is {}", other.type_name()),
                )
                .with_note(format!("usage: {}", directive.signature()))),
            }
        };
        let text = |i: usize| -> Result<&str, Diagnostic> {
            match args[i] {
                Value::Str(s) => Ok(names.text(s)),
                other => Err(error(
                    "expected a string",
                    arg_spans[i],
                    format!("this is {}", other.type_name()),
                )
                .with_note(format!("usage: {}", directive.signature()))),
            }
        };
        let positive = |i: usize, what: &str| -> Result<f64, Diagnostic> {
            let v = number(i)?;
            if v > 0.0 {
                Ok(v)
            } else {
                Err(error(
                    format!("{what} must be positive"),
                    arg_spans[i],
                    "not > 0",
                ))
            }
        };
        let key = match directive {
            Directive::Units => {
                if args.len() != 1 {
                    return Err(arity_error("1 argument"));
                }
                let units = match text(0)?.to_ascii_lowercase().as_str() {
                    "inch" | "in" => Units::Inch,
                    "mm" => Units::Mm,
                    other => {
                        return Err(error(
                            format!("unknown units \"{other}\""),
                            arg_spans[0],
                            "expected \"inch\" or \"mm\"",
                        ))
                    }
                };
                self.define((directive, 0), span)?;
                self.setup.units = Some(units);
                return Ok(());
            }
            Directive::Margin => {
                if args.len() != 1 {
                    return Err(arity_error("1 argument"));
                }
                let m = number(0)?;
                if m < 0.0 {
                    return Err(error("negative margin", arg_spans[0], "must be 0 or more"));
                }
                self.setup.margin = Some(m);
                (directive, 0)
            }
            Directive::Part | Directive::Zero => {
                if args.len() != 3 {
                    return Err(arity_error("3 arguments"));
                }
                let v = if directive == Directive::Part {
                    [
                        positive(0, "the stock size")?,
                        positive(1, "the stock size")?,
                        positive(2, "the stock size")?,
                    ]
                } else {
                    [number(0)?, number(1)?, number(2)?]
                };
                if directive == Directive::Part {
                    self.setup.part = Some(v);
                } else {
                    self.setup.zero = Some(v);
                }
                (directive, 0)
            }
            Directive::Tool => {
                if !(2..=4).contains(&args.len()) {
                    return Err(arity_error("2 to 4 arguments"));
                }
                let n = number(0)?;
                if n < 0.0 || n.fract() != 0.0 || n > 99_999.0 {
                    return Err(error(
                        "invalid tool number",
                        arg_spans[0],
                        "a whole number from 0",
                    ));
                }
                let diameter = positive(1, "the tool diameter")?;
                let mut length = 0.0;
                let mut shape = ToolShape::Flat;
                for i in 2..args.len() {
                    match args[i] {
                        Value::Number(l) if i == 2 => length = l,
                        Value::Str(s) if i == args.len() - 1 => {
                            shape = ToolShape::from_name(names.text(s)).ok_or_else(|| {
                                error(
                                    format!("unknown tool shape \"{}\"", names.text(s)),
                                    arg_spans[i],
                                    "expected \"flat\", \"ball\", \"drill\" or \"vee\"",
                                )
                            })?
                        }
                        _ => return Err(arity_error("number, diameter, [length], [shape]")),
                    }
                }
                let key = (directive, n as u32);
                self.define(key, span)?;
                self.setup.tools.insert(
                    n as u32,
                    Tool {
                        diameter,
                        length: Some(length),
                        shape,
                    },
                );
                return Ok(());
            }
            Directive::Offset => {
                if args.len() != 4 {
                    return Err(arity_error("4 arguments"));
                }
                let n = number(0)?;
                if !(55.0..=59.0).contains(&n) || n.fract() != 0.0 {
                    return Err(error(
                        "invalid work offset",
                        arg_spans[0],
                        "SetOffset takes 55 to 59 (G54 is the program zero itself)",
                    ));
                }
                let index = (n as u32 - 53) as u8;
                let key = (directive, index as u32);
                self.define(key, span)?;
                self.setup
                    .work_offsets
                    .insert(index, [number(1)?, number(2)?, number(3)?]);
                return Ok(());
            }
        };
        self.define(key, span)
    }

    fn define(&mut self, key: (Directive, u32), span: Span) -> Result<(), Diagnostic> {
        if let Some(&first) = self.defined.get(&key) {
            return Err(error(
                format!("{} given twice", Directive::NAMES[key.0 as usize]),
                span,
                "second definition",
            )
            .with_secondary(first, "first definition"));
        }
        self.defined.insert(key, span);
        Ok(())
    }
}
