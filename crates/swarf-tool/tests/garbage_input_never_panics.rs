//! Readers and the spec parser return errors, never panic, on arbitrary text.

use proptest::prelude::*;
use swarf_tool::table::{parse_camotics, parse_linuxcnc, parse_toml_library};
use swarf_tool::{Cutter, LengthUnit};

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(256))]
    #[test]
    fn spec_parser(s in "\\PC{0,40}") {
        let _ = Cutter::from_spec(&s);
    }

    #[test]
    fn spec_parser_near_valid(kind in "(flat|ball|bull|apt|drill|chamfer|taper-ball|taper-flat)",
                              rest in "[-a-z0-9=.,: eé]{0,30}") {
        let _ = Cutter::from_spec(&format!("{kind}:{rest}"));
    }

    #[test]
    fn table_readers(s in "\\PC{0,200}") {
        let _ = parse_linuxcnc(&s, "f.tbl", LengthUnit::Mm);
        let _ = parse_toml_library(&s, "f.toml");
        let _ = parse_camotics(&s, "f.camotics");
    }

    #[test]
    fn linuxcnc_near_valid(lines in proptest::collection::vec("[TPDZXIJQ]-?[0-9.e+]{0,6}( [TPDZXIJQ;][-0-9.]{0,5}){0,4}", 0..6)) {
        let _ = parse_linuxcnc(&lines.join("\n"), "f.tbl", LengthUnit::Inch);
    }
}
