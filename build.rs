//! Build script: generates the LALRPOP parser from `grammar/*.lalrpop` into
//! `$OUT_DIR`. It must not do anything else (no code generation of our own).

fn main() {
    lalrpop::Configuration::new()
        .set_in_dir("grammar")
        .set_out_dir(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .emit_rerun_directives(true)
        .process()
        .expect("grammar/ger.lalrpop must generate");
}
