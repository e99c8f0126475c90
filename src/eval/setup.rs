//! Setup directives (SPEC §3): `SetUnits`, `SetMargin`, `SetPart`,
//! `SetZero`, `SetTool`, `SetOffset`. They fill one machine model,
//! [`ir::Setup`]; defining the same thing twice is an error that shows both.

use super::value::Value;
use crate::ast::Names;
use crate::diagnostic::{error, Diagnostic, DiagnosticExt, Located, Wording};
use crate::ir::{self, Tool, ToolShape, Units};
use crate::source::Span;
use std::collections::{BTreeMap, HashMap};

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
    /// `--tool-units`: the units of the `--tool-table` entries no
    /// `SetTool` redefined; `None`: the output's.
    table_units: Option<Units>,
    /// Where each thing was defined, for "defined twice".
    defined: HashMap<(Directive, u32), Span>,
    /// What `G10 L1`/`L10`/`L11` set at run time, over the above (kept
    /// apart: the output's start holds the setup before them).
    set_by_g10: BTreeMap<u32, SetByG10>,
}

/// A tool's values a G10 set.
#[derive(Clone, Copy, Debug, Default)]
struct SetByG10 {
    /// The diameter, in the units in force at the G10 (`None`: the
    /// program's numbers, its units unstated).
    diameter: Option<(f64, Option<Units>)>,
    /// The length; `Some(None)`: an L10/L11's, which only the offsets pass
    /// works out.
    length: Option<Option<f64>>,
}

impl SetupBuilder {
    /// A setup whose tool table starts with `tools` (`--tool-table`); the
    /// program's `SetTool` may redefine them.
    /// `table_units`: theirs (`--tool-units`), else the output's.
    pub fn with_tools(
        tools: &std::collections::BTreeMap<u32, ir::Tool>,
        table_units: Option<Units>,
    ) -> SetupBuilder {
        let mut builder = SetupBuilder::default();
        builder.setup.tools = tools.clone();
        builder.table_units = table_units;
        builder
    }

    /// The setup with the table's tools in `output` units (the setup's,
    /// SPEC §3); where those are unknown, as the table gives them.
    pub fn in_units(&self, output: Option<Units>) -> ir::Setup {
        let mut setup = self.setup.clone();
        let (Some(from), Some(to)) = (self.table_units, output) else {
            return setup;
        };
        let k = from.factor(to);
        for (number, tool) in setup.tools.iter_mut() {
            if !self.defined.contains_key(&(Directive::Tool, *number)) {
                tool.diameter *= k;
                tool.length = tool.length.map(|l| l * k);
            }
        }
        setup
    }

    /// The setup as defined so far.
    pub fn get(&self) -> &ir::Setup {
        &self.setup
    }

    /// A `G10 L1`/`L10`/`L11`'s values from here on (`units`: those in
    /// force at it), as the passes and the tool path apply it.
    pub fn set_tool_data(&mut self, data: &ir::ToolData, units: Option<Units>) {
        let entry = self.set_by_g10.entry(data.tool).or_default();
        if let Some(r) = data.radius {
            entry.diameter = Some((2.0 * r, units));
        }
        if let Some(length) = data.length {
            entry.length = Some((data.measured == ir::Measured::Given).then_some(length));
        }
    }

    /// Whether a tool's length is zero (`None`: not known here).
    pub fn tool_length_is_zero(&self, tool: u32) -> Option<bool> {
        let length = match self.set_by_g10.get(&tool).and_then(|t| t.length) {
            Some(length) => length,
            None => self.setup.tools.get(&tool)?.length,
        };
        length.map(|l| l == 0.0)
    }

    /// Diameter of a tool in the program's current units (for wizards).
    pub fn tool_diameter(&self, tool: u32, program_units: Option<Units>) -> f64 {
        let setup_units = self.setup.units.or(program_units).unwrap_or(Units::Inch);
        let to = program_units.unwrap_or(setup_units);
        if let Some((d, units)) = self.set_by_g10.get(&tool).and_then(|t| t.diameter) {
            return d * units.map_or(1.0, |from| from.factor(to));
        }
        let table_units = match self.defined.contains_key(&(Directive::Tool, tool)) {
            true => setup_units,
            false => self.table_units.unwrap_or(setup_units),
        };
        match self.setup.tools.get(&tool) {
            Some(t) => t.diameter * table_units.factor(to),
            None => DEFAULT_TOOL_DIAMETER_INCH * Units::Inch.factor(to),
        }
    }

    /// The included angle (degrees) of a vee tool; `None` for other shapes.
    pub fn tool_angle(&self, tool: u32) -> Option<f64> {
        match self.setup.tools.get(&tool)?.shape {
            ToolShape::Vee(angle) => Some(angle),
            ToolShape::Flat | ToolShape::Ball | ToolShape::Drill => None,
        }
    }

    pub fn apply(
        &mut self,
        directive: Directive,
        args: &[Value],
        span: Span,
        arg_spans: &[Span],
        names: &Names,
    ) -> Result<(), SetupError> {
        let a = Args {
            directive,
            values: args,
            span,
            spans: arg_spans,
            names,
        };
        match directive {
            Directive::Units => self.units(&a),
            Directive::Margin => self.margin(&a),
            Directive::Part | Directive::Zero => self.part_or_zero(&a),
            Directive::Tool => self.tool(&a),
            Directive::Offset => self.offset(&a),
        }
    }

    /// `SetUnits "inch"|"mm"`.
    fn units(&mut self, a: &Args<'_>) -> Result<(), SetupError> {
        a.arity(1..=1, "1 argument")?;
        let units = match a.text(0)?.to_ascii_lowercase().as_str() {
            "inch" | "in" => Units::Inch,
            "mm" => Units::Mm,
            other => {
                return Err(SetupError::new(
                    SetupErrorKind::UnknownUnits(other.to_string()),
                    a.spans[0],
                ))
            }
        };
        self.define((a.directive, 0), a.span)?;
        self.setup.units = Some(units);
        Ok(())
    }

    /// `SetMargin m`.
    fn margin(&mut self, a: &Args<'_>) -> Result<(), SetupError> {
        a.arity(1..=1, "1 argument")?;
        let m = a.number(0)?;
        if m < 0.0 {
            return Err(SetupError::new(SetupErrorKind::NegativeMargin, a.spans[0]));
        }
        self.setup.margin = Some(m);
        self.define((a.directive, 0), a.span)
    }

    /// `SetPart x y z` (the stock) or `SetZero x y z`.
    fn part_or_zero(&mut self, a: &Args<'_>) -> Result<(), SetupError> {
        a.arity(3..=3, "3 arguments")?;
        if a.directive == Directive::Part {
            let size = |i| a.positive(i, "the stock size");
            self.setup.part = Some([size(0)?, size(1)?, size(2)?]);
        } else {
            self.setup.zero = Some([a.number(0)?, a.number(1)?, a.number(2)?]);
        }
        self.define((a.directive, 0), a.span)
    }

    /// `SetTool n diameter [length] [shape]`; without a length, the
    /// tool's length is not known (a G43 for it passes through).
    fn tool(&mut self, a: &Args<'_>) -> Result<(), SetupError> {
        a.arity(2..=4, "2 to 4 arguments")?;
        let n = a.number(0)?;
        if n < 0.0 || n.fract() != 0.0 || n > 99_999.0 {
            return Err(SetupError::new(SetupErrorKind::ToolNumber, a.spans[0]));
        }
        let diameter = a.positive(1, "the tool diameter")?;
        let mut length = None;
        let mut shape = ToolShape::Flat;
        for i in 2..a.values.len() {
            match a.values[i] {
                Value::Number(_) if i == 2 => length = Some(a.number(2)?),
                Value::Str(s) if i == a.values.len() - 1 => {
                    shape = ToolShape::from_name(a.names.text(s)).ok_or_else(|| {
                        SetupError::new(
                            SetupErrorKind::ToolShape(a.names.text(s).to_string()),
                            a.spans[i],
                        )
                    })?
                }
                _ => return Err(a.arity_error("number, diameter, [length], [shape]")),
            }
        }
        self.define((a.directive, n as u32), a.span)?;
        self.setup.tools.insert(
            n as u32,
            Tool {
                diameter,
                length,
                shape,
            },
        );
        Ok(())
    }

    /// `SetOffset 55..59 x y z`.
    fn offset(&mut self, a: &Args<'_>) -> Result<(), SetupError> {
        a.arity(4..=4, "4 arguments")?;
        let n = a.number(0)?;
        if !(55.0..=59.0).contains(&n) || n.fract() != 0.0 {
            return Err(SetupError::new(SetupErrorKind::WorkOffset, a.spans[0]));
        }
        let index = (n as u32 - 53) as u8;
        self.define((a.directive, index as u32), a.span)?;
        let origin = [a.number(1)?, a.number(2)?, a.number(3)?];
        self.setup.work_offsets.insert(index, origin);
        Ok(())
    }

    fn define(&mut self, key: (Directive, u32), span: Span) -> Result<(), SetupError> {
        if let Some(&first) = self.defined.get(&key) {
            return Err(SetupError::new(
                SetupErrorKind::Twice {
                    directive: key.0,
                    first,
                },
                span,
            ));
        }
        self.defined.insert(key, span);
        Ok(())
    }
}

/// The arguments of one directive call, with the checks every directive
/// makes.
struct Args<'a> {
    directive: Directive,
    values: &'a [Value],
    span: Span,
    spans: &'a [Span],
    names: &'a Names,
}

impl Args<'_> {
    fn arity(
        &self,
        count: std::ops::RangeInclusive<usize>,
        wanted: &'static str,
    ) -> Result<(), SetupError> {
        if count.contains(&self.values.len()) {
            Ok(())
        } else {
            Err(self.arity_error(wanted))
        }
    }

    fn arity_error(&self, wanted: &'static str) -> SetupError {
        let at = self.spans.first().map_or(self.span, |first| {
            first.to(*self.spans.last().unwrap_or(first))
        });
        SetupError::new(
            SetupErrorKind::Arity {
                directive: self.directive,
                wanted,
                given: self.values.len(),
            },
            at,
        )
    }

    fn number(&self, i: usize) -> Result<f64, SetupError> {
        match self.values[i] {
            Value::Number(n) if !ir::is_length(n) => Err(SetupError::new(
                SetupErrorKind::OutOfRange(n),
                self.spans[i],
            )),
            Value::Number(n) => Ok(n),
            other => Err(self.wrong_type(i, "a number", other)),
        }
    }

    fn text(&self, i: usize) -> Result<&str, SetupError> {
        match self.values[i] {
            Value::Str(s) => Ok(self.names.text(s)),
            other => Err(self.wrong_type(i, "a string", other)),
        }
    }

    fn wrong_type(&self, i: usize, expected: &'static str, found: Value) -> SetupError {
        SetupError::new(
            SetupErrorKind::WrongType {
                directive: self.directive,
                expected,
                found: found.type_name(),
            },
            self.spans[i],
        )
    }

    fn positive(&self, i: usize, what: &'static str) -> Result<f64, SetupError> {
        let v = self.number(i)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(SetupError::new(
                SetupErrorKind::NotPositive(what),
                self.spans[i],
            ))
        }
    }
}

/// What a setup directive can get wrong.
#[derive(Clone, Debug, PartialEq)]
pub enum SetupErrorKind {
    UnknownUnits(String),
    NegativeMargin,
    ToolNumber,
    ToolShape(String),
    WorkOffset,
    /// The same entry again; the span of the first.
    Twice {
        directive: Directive,
        first: Span,
    },
    Arity {
        directive: Directive,
        wanted: &'static str,
        given: usize,
    },
    OutOfRange(f64),
    WrongType {
        directive: Directive,
        expected: &'static str,
        found: &'static str,
    },
    /// What must be positive.
    NotPositive(&'static str),
}

/// What goes wrong, and where: see [`SetupErrorKind`].
pub type SetupError = Located<SetupErrorKind>;

impl Wording for SetupErrorKind {
    fn wording(&self, at: Span) -> Diagnostic {
        let usage = |d: &Directive| format!("usage: {}", d.signature());
        match self {
            SetupErrorKind::UnknownUnits(units) => error(
                format!("unknown units \"{units}\""),
                at,
                "expected \"inch\" or \"mm\"",
            ),
            SetupErrorKind::NegativeMargin => error("negative margin", at, "must be 0 or more"),
            SetupErrorKind::ToolNumber => error("invalid tool number", at, "a whole number from 0"),
            SetupErrorKind::ToolShape(shape) => error(
                format!("unknown tool shape \"{shape}\""),
                at,
                "expected \"flat\", \"ball\", \"drill\" or \"vee\"",
            ),
            SetupErrorKind::WorkOffset => error(
                "invalid work offset",
                at,
                "SetOffset takes 55 to 59 (G54 is the program zero itself)",
            ),
            SetupErrorKind::Twice { directive, first } => error(
                format!("{} given twice", Directive::NAMES[*directive as usize]),
                at,
                "second definition",
            )
            .with_secondary(*first, "first definition"),
            SetupErrorKind::Arity {
                directive,
                wanted,
                given,
            } => error(
                format!(
                    "wrong arguments for {}",
                    Directive::NAMES[*directive as usize]
                ),
                at,
                format!("{wanted}, {given} given"),
            )
            .with_note(usage(directive)),
            SetupErrorKind::OutOfRange(n) => {
                super::error::out_of_range("out of range".into(), "numbers here", *n, at)
            }
            SetupErrorKind::WrongType {
                directive,
                expected,
                found,
            } => error(
                format!("expected {expected}"),
                at,
                format!("this is {found}"),
            )
            .with_note(usage(directive)),
            SetupErrorKind::NotPositive(what) => {
                error(format!("{what} must be positive"), at, "not > 0")
            }
        }
    }
}
