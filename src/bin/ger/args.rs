//! The command line's words: the subcommands and their options (clap),
//! turned into the library's options. Nothing here reads a file.

use clap::{Parser, Subcommand, ValueEnum};
use ger::driver::discovery::Search;
use ger::driver::CompileOptions;
use ger::driver::Stage;
use ger::emit::{ArcFormat, Numbering, Target};
use ger::ir::Units;
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "ger",
    version,
    about = "Compile extended G-code (.egc) to plain ISO G-code"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Compile a program to plain G-code.
    Compile {
        /// The .egc file, or `-` for standard input.
        input: String,
        /// Output file (standard output when absent, or `-`).
        #[arg(short, long)]
        output: Option<PathBuf>,
        #[command(flatten)]
        options: Options,
        #[arg(long, help = stage_help())]
        stage: Option<String>,
    },
    /// Check a program and print its diagnostics; write nothing.
    Check {
        input: String,
        #[command(flatten)]
        options: Options,
    },
    /// Draw the part the program cuts: a depth (or --shade) PNG, the tool
    /// path as SVG, or the part as STL, by the output's extension.
    Render {
        /// The program, or `-` for standard input.
        input: String,
        /// The picture: part.png, part.svg or part.stl.
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        options: Options,
        #[command(flatten)]
        picture: PictureArgs,
    },
    /// How long the program runs on the machine of ger.toml's `[machine]`
    /// (planned as its controller plans it), beside length / feed; cut and
    /// rapid lengths, dwells, tool changes, and per tool its time, cut and
    /// bounds.
    Stats {
        /// The program, or `-` for standard input.
        input: String,
        #[command(flatten)]
        options: Options,
        /// One JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// The part in 3D in the browser: the cut played back, each move
    /// linked to its line, redrawn when a file it uses changes.
    View {
        /// The program.
        input: String,
        /// One self-contained page to keep or send (no server).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// The server's port on 127.0.0.1 (default: any free one).
        #[arg(long, default_value_t = 0)]
        port: u16,
        /// Print the page's address without opening a browser.
        #[arg(long)]
        no_open: bool,
        #[command(flatten)]
        options: Options,
        #[command(flatten)]
        stock: StockArgs,
    },
    /// The language server for editors (LSP on standard input and output):
    /// diagnostics as you type, and where the tool is after each line.
    Lsp,
    /// The machine profile: `ger machine import FILE` prints the
    /// `[machine]` table of ger.toml for a LinuxCNC INI or a grbl `$$` dump.
    Machine {
        #[command(subcommand)]
        action: MachineCommand,
    },
    /// List the wizards found, or show one wizard's signature and doc.
    #[command(after_help = standard_wizards())]
    Wizards {
        name: Option<String>,
        /// A folder of wizards (`<Name>.rhai`), searched first; repeatable.
        #[arg(long = "wizards", value_name = "DIR")]
        dirs: Vec<PathBuf>,
        /// Also search the `wizards/` folder beside this part program.
        #[arg(long)]
        part: Option<PathBuf>,
    },
}

#[derive(clap::Args)]
pub struct Options {
    /// Line numbers: the source line (default), a sequence, the program's
    /// own N words (keep), or none.
    #[arg(long, value_enum, default_value_t = NumbersArg::Source)]
    pub numbers: NumbersArg,
    /// The output flavour.
    #[arg(long, alias = "dialect", value_enum, default_value_t = TargetArg::Generic)]
    pub target: TargetArg,
    /// Comments of a plain G-code program in the output.
    #[arg(long, value_enum, default_value_t = CommentsArg::Keep)]
    pub comments: CommentsArg,
    /// The source language; default: `.egc` is ger's, any other file plain G-code.
    #[arg(long = "input", id = "language", value_name = "LANGUAGE", value_enum)]
    pub language: Option<InputArg>,
    /// Whose meaning holds where controllers disagree (G4 P in s or ms);
    /// default: linuxcnc for .ngc files, else the --target's controller,
    /// else grbl's `$H` or a Fanuc `%` tape with an O number in the first
    /// lines, else generic (P in seconds).
    #[arg(long, value_enum)]
    pub from: Option<FromArg>,
    /// A LinuxCNC tool table (`T1 P1 D6.35 Z75`), in --tool-units (else
    /// the output's units); the program's `SetTool` lines win over it.
    #[arg(long = "tool-table", value_name = "FILE")]
    pub tool_table: Option<PathBuf>,
    /// The units of the --tool-table (a LinuxCNC table is in the
    /// machine's units, its INI's); default: the output's.
    #[arg(long = "tool-units", value_enum)]
    pub tool_units: Option<UnitsArg>,
    /// The units of a program that states none (no G20/G21, no SetUnits).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Canned cycles: expanded to moves, or kept for a controller that has
    /// them (--target fanuc or linuxcnc).
    #[arg(long, value_enum, default_value_t = CyclesArg::Expand)]
    pub cycles: CyclesArg,
    /// Cutter compensation: resolved into the tool-centre path, or kept for
    /// a controller that compensates itself (--target fanuc or linuxcnc).
    #[arg(long, value_enum, default_value_t = CompArg::Resolve)]
    pub comp: CompArg,
    /// The move that starts compensation: rs274's (offset square to itself
    /// at its end, then a corner) or lookahead (straight to the offset start
    /// of the next move, as Ger does).
    #[arg(long = "comp-entry", value_enum, default_value_t = CompEntryArg::Rs274)]
    pub comp_entry: CompEntryArg,
    /// How arcs are written.
    #[arg(long, value_enum, default_value_t = ArcsArg::Ij)]
    pub arcs: ArcsArg,
    /// Chord tolerance for `--arcs lines` (default 0.001) and `--arcs fit`
    /// (default 0.005 mm, 0.0002 in), in output units.
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Decimals in the output (default 3 for mm, 4 for inch).
    #[arg(long)]
    pub decimals: Option<usize>,
    /// A `while` loop that runs more often is an error.
    #[arg(long, default_value_t = 10_000_000)]
    pub max_iterations: u64,
    /// Print the time each stage took to stderr.
    #[arg(long)]
    pub timings: bool,
    /// A folder of wizards (`<Name>.rhai`), searched first; repeatable.
    #[arg(long = "wizards", value_name = "DIR")]
    pub wizard_dirs: Vec<PathBuf>,
    /// A folder of LinuxCNC subroutine files (`name.ngc` for `o<name>
    /// call`), searched before the program's own folder; repeatable.
    #[arg(long = "subroutines", value_name = "DIR")]
    pub subroutine_dirs: Vec<PathBuf>,
    /// The `ger.toml` keys this command line set (they win over the file).
    #[arg(skip)]
    pub given: Vec<&'static str>,
}

#[derive(Subcommand)]
pub enum MachineCommand {
    /// Print the `[machine]` table for a LinuxCNC INI file or grbl's `$$`
    /// settings dump (`-` reads standard input).
    Import { file: String },
}

/// Each `ger.toml` key of `[compile]` and the id of its flag.
const FLAGS: [(&str, &str); 17] = [
    ("target", "target"),
    ("from", "from"),
    ("input", "language"),
    ("units", "units"),
    ("tool-table", "tool_table"),
    ("tool-units", "tool_units"),
    ("arcs", "arcs"),
    ("tolerance", "tolerance"),
    ("decimals", "decimals"),
    ("cycles", "cycles"),
    ("comp", "comp"),
    ("comp-entry", "comp_entry"),
    ("numbers", "numbers"),
    ("comments", "comments"),
    ("max-iterations", "max_iterations"),
    ("wizards", "wizard_dirs"),
    ("subroutines", "subroutine_dirs"),
];

/// The command line, with the `ger.toml` keys each subcommand's flags set.
pub fn parse() -> Cli {
    use clap::{CommandFactory, FromArgMatches};
    let matches = Cli::command().get_matches();
    let mut cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    let Some((_, sub)) = matches.subcommand() else {
        return cli;
    };
    let given: Vec<&'static str> = FLAGS
        .iter()
        .filter(|(_, id)| {
            sub.try_get_raw(id).is_ok_and(|v| v.is_some())
                && sub.value_source(id) == Some(clap::parser::ValueSource::CommandLine)
        })
        .map(|(key, _)| *key)
        .collect();
    match &mut cli.command {
        Command::Compile { options, .. }
        | Command::Check { options, .. }
        | Command::Render { options, .. }
        | Command::View { options, .. }
        | Command::Stats { options, .. } => options.given = given,
        Command::Machine { .. } | Command::Wizards { .. } | Command::Lsp => {}
    }
    cli
}

#[derive(clap::Args)]
pub struct PictureArgs {
    /// The cell size, in the program's units (default 0.001 in / 0.025 mm).
    #[arg(long)]
    pub resolution: Option<f64>,
    /// Coarser cells when the stock would need more than this many.
    #[arg(long, default_value_t = 40_000_000)]
    pub max_cells: u64,
    /// The stock's size X,Y,Z (placed as SetPart places it).
    #[arg(long, value_name = "X,Y,Z")]
    pub stock: Option<String>,
    /// A hill-shaded colour PNG with a depth legend instead of the depth image.
    #[arg(long)]
    pub shade: bool,
    /// The cut part as a lit 3D picture (PNG) seen from this side, instead
    /// of the depth image.
    #[arg(long, value_enum)]
    pub view: Option<ViewArg>,
    /// The long side of a --view or --shade picture, in pixels.
    #[arg(long, value_name = "PIXELS", default_value_t = 1600)]
    pub size: usize,
    /// Draw the tool path over a --view picture.
    #[arg(long)]
    pub toolpath: bool,
    /// What colours the feeds of an SVG.
    #[arg(long, value_enum, default_value_t = ColorArg::Depth)]
    pub color: ColorArg,
    /// Rapids in an SVG.
    #[arg(long, value_enum, default_value_t = RapidsArg::Show)]
    pub rapids: RapidsArg,
    /// Another program: the PNG shows where the two cut differently.
    #[arg(long, value_name = "OTHER")]
    pub diff: Option<String>,
}

/// The stock `ger view` carves, as `ger render` takes it.
#[derive(clap::Args)]
pub struct StockArgs {
    /// The cell size, in the program's units (default 0.001 in / 0.025 mm).
    #[arg(long)]
    pub resolution: Option<f64>,
    /// Coarser cells when the stock would need more than this many.
    #[arg(long, default_value_t = 40_000_000)]
    pub max_cells: u64,
    /// The stock's size X,Y,Z (placed as SetPart places it).
    #[arg(long, value_name = "X,Y,Z")]
    pub stock: Option<String>,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ViewArg {
    Top,
    Iso,
    Front,
    Side,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ColorArg {
    Depth,
    Feed,
    Tool,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RapidsArg {
    Show,
    Hide,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum NumbersArg {
    Source,
    Seq,
    Keep,
    None,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CommentsArg {
    Keep,
    Drop,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum FromArg {
    Generic,
    Linuxcnc,
    Fanuc,
    Grbl,
    Mach3,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum InputArg {
    Egc,
    Gcode,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum UnitsArg {
    Mm,
    Inch,
}

impl UnitsArg {
    fn units(self) -> Units {
        match self {
            UnitsArg::Mm => Units::Mm,
            UnitsArg::Inch => Units::Inch,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
pub enum TargetArg {
    Generic,
    Fanuc,
    Grbl,
    Linuxcnc,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CyclesArg {
    Expand,
    Keep,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CompArg {
    Resolve,
    Keep,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CompEntryArg {
    Rs274,
    Lookahead,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum ArcsArg {
    Ij,
    R,
    Lines,
    Fit,
    FitR,
}

impl Options {
    /// The library's options for these command-line choices.
    pub fn compile_options(&self, stage: Option<Stage>) -> CompileOptions {
        CompileOptions {
            eval: ger::eval::EvalOptions {
                max_iterations: self.max_iterations,
                keep_comments: self.comments == CommentsArg::Keep,
                units: self.units.map(UnitsArg::units),
                tool_units: self.tool_units.map(UnitsArg::units),
                ..Default::default()
            },
            from: self.from.map(|f| match f {
                FromArg::Generic => ger::eval::Flavour::Generic,
                FromArg::Linuxcnc => ger::eval::Flavour::LinuxCnc,
                FromArg::Fanuc => ger::eval::Flavour::Fanuc,
                FromArg::Grbl => ger::eval::Flavour::Grbl,
                FromArg::Mach3 => ger::eval::Flavour::Mach3,
            }),
            input: self.language.map(|i| match i {
                InputArg::Egc => ger::syntax::Language::Egc,
                InputArg::Gcode => ger::syntax::Language::Gcode,
            }),
            lower: ger::lower::LowerOptions {
                keep_cycles: self.cycles == CyclesArg::Keep,
                keep_comp: self.comp == CompArg::Keep,
                comp_entry_lookahead: self.comp_entry == CompEntryArg::Lookahead,
                tip_path: false,
            },
            emit: ger::emit::EmitOptions {
                numbering: match self.numbers {
                    NumbersArg::Source => Numbering::Source,
                    NumbersArg::Seq => Numbering::Seq,
                    NumbersArg::Keep => Numbering::Keep,
                    NumbersArg::None => Numbering::None,
                },
                target: match self.target {
                    TargetArg::Generic => Target::Generic,
                    TargetArg::Fanuc => Target::Fanuc,
                    TargetArg::Grbl => Target::Grbl,
                    TargetArg::Linuxcnc => Target::LinuxCnc,
                },
                arcs: match self.arcs {
                    ArcsArg::Ij => ArcFormat::Ij,
                    ArcsArg::R => ArcFormat::R,
                    ArcsArg::Lines => ArcFormat::Lines,
                    ArcsArg::Fit => ArcFormat::Fit,
                    ArcsArg::FitR => ArcFormat::FitR,
                },
                decimals: self.decimals,
                tolerance: self.tolerance,
                ..Default::default()
            },
            stage,
            library: Vec::new(),
            travel: None,
        }
    }
}

impl Options {
    /// Where the program's wizards, subroutine files and tool table are
    /// found: these options, and the `GER_WIZARDS` folders.
    pub fn search(&self) -> Search {
        Search {
            wizard_dirs: self.wizard_dirs.clone(),
            wizard_path: wizard_path(),
            subroutine_dirs: self.subroutine_dirs.clone(),
            tool_table: self.tool_table.clone(),
        }
    }
}

/// The `GER_WIZARDS` folders.
pub fn wizard_path() -> Vec<PathBuf> {
    std::env::var_os("GER_WIZARDS")
        .map(|env| std::env::split_paths(&env).collect())
        .unwrap_or_default()
}

/// `--stage`'s help: every stage, from the registry.
fn stage_help() -> String {
    let names: Vec<&str> = Stage::names().collect();
    format!("Print the program after this stage ({})", names.join(", "))
}

/// `ger wizards --help`: the standard library's wizards, by name.
fn standard_wizards() -> String {
    let mut names: Vec<String> = ger::wizard::standard_library()
        .into_iter()
        .map(|w| w.name)
        .collect();
    names.sort_by_key(|n| n.to_lowercase());
    format!("Standard wizards: {}", names.join(", "))
}
