//! The program after one stage (`--stage`): every statement as written,
//! modal codes included, so a reader sees what the stage did.

use super::printer::Printer;
use super::{Numbering, Target};
use crate::ir::{self, Units};

pub struct StagePrinter {
    p: Printer,
}

impl StagePrinter {
    pub fn new(units: Option<Units>, source_len: usize, main_file: usize) -> StagePrinter {
        StagePrinter {
            p: Printer::new(
                Numbering::Source,
                Target::Generic,
                None,
                units,
                main_file,
                source_len * 2,
            ),
        }
    }

    /// Print the next statements of the program; returns the text not
    /// yet taken (the caller may take it).
    pub fn print(&mut self, stmts: &[ir::Stmt]) -> &mut Vec<u8> {
        for stmt in stmts {
            self.p.stmt(stmt);
        }
        &mut self.p.out
    }

    /// The rest of the text.
    pub fn finish(self) -> Vec<u8> {
        self.p.out
    }
}
