//! LinuxCNC G-code read as LinuxCNC 2.9's `rs274` reads it, found by differential testing of
//! random programs (motion, offsets, tools, O-words, parameters, messages) against the real
//! `rs274 -g` (Debian's linuxcnc 2.9 interpreter, with `-t` a tool table in inches). Every
//! expected listing below is what rs274 printed for the program above it, written in as it
//! printed it (the motion calls and `MESSAGE`s); where rs274 stopped with an error, its message
//! is quoted in a comment and swarf must stop at the same line.

mod common;

use common::{canonical, listing as lines};
use swarf_path::gcode::GcodeOptions;
use swarf_path::{PathError, Units};

/// swarf's canonical print of `src`, as `swarf path --canonical` prints it, with the
/// standalone rs274's offset parameters in inches; and the error that stopped it, if any.
fn canon(src: &str) -> (String, Option<PathError>) {
    canonical(
        src,
        &GcodeOptions::default().with_parameter_units(Units::Inch),
    )
}

#[track_caller]
fn same(src: &str, expected: &str) {
    let (out, err) = canon(src);
    assert!(err.is_none(), "{err:?}");
    assert_eq!(out, lines(expected));
}

#[track_caller]
fn stops_at(src: &str, line: u32, expected: &str) -> PathError {
    let (out, err) = canon(src);
    let err = err.unwrap_or_else(|| panic!("no error; printed\n{out}"));
    assert_eq!(err.pos.line, line, "{err}");
    assert_eq!(out, lines(expected));
    err
}

/// convert_feed_mode zeroes the feed rate at every G94 and G95, even in that mode already.
#[test]
fn g94_forgets_the_feed_even_in_g94() {
    // rs274: "Cannot do g1 with zero feed rate" at `G1 X2`.
    stops_at(
        "G21 G94 F100\nG1 X1\nG94\nG1 X2\nM2\n",
        4,
        "N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    // G93 keeps it (every G93 move carries its own F).
    same(
        "G21 G93\nG1 X1 F10\nG94 F50\nG1 X2\nM2\n",
        "N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// G95 feeds need a spindle speed (an S word; the spindle need not turn).
#[test]
fn g95_feeds_need_a_spindle_speed() {
    // rs274: "Cannot feed with zero spindle speed in feed per rev mode" at `G1 X1`.
    stops_at("G21 G95 F0.1\nS0 M3\nG1 X1\nM2\n", 3, "");
    same(
        "G21 G95 F0.1\nS100\nG1 X1\nG2 X3 R1\nM2\n",
        "N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... ARC_FEED(3.0000, 0.0000, 2.0000, -0.0000, -1, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    // rs274: "Cannot feed with zero spindle speed in feed per rev mode" at the arc.
    stops_at("G21 G95 F0.1\nG2 X3 R2\nM2\n", 2, "");
}

/// convert_setup: "R not allowed in G10 L20".
#[test]
fn g10_l20_refuses_r() {
    stops_at(
        "G21\nG0 X1\nG10 L20 P1 X0 R10\nG0 X2\nM2\n",
        3,
        "N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// rs274 starts with feed hold enabled and selected tool 0.
#[test]
fn feed_hold_and_selected_tool_at_the_start() {
    same(
        "G21\n(DEBUG, #<_feed_hold> #<_selected_tool>)\nT3\n(DEBUG, #<_selected_tool>)\n\
         M53 P0\n(DEBUG, #<_feed_hold>)\nM2\n",
        r#"N..... MESSAGE(" 1.000000 0.000000")
           N..... MESSAGE(" 3.000000")
           N..... MESSAGE(" 0.000000")"#,
    );
}

/// read_o reads a subroutine's `endsub [value]` (and `return [value]`) while it skips the
/// definition: `#<_value>` and `#<_value_returned>` change, and a bad expression is an error.
#[test]
fn endsub_values_are_read_at_the_definition() {
    let err = stops_at(
        "G21\no<s> sub\no<s> endsub [7]\n(DEBUG, #<_value> #<_value_returned>)\n\
         o<t> sub\no<t> endsub\n(DEBUG, #<_value> #<_value_returned>)\n\
         o<u> sub\no<u> endsub [1/0]\nG0 X1\nM2\n",
        // rs274: "Attempt to divide by zero" at `o<u> endsub [1/0]` (line 9); swarf stops at
        // the definition's `sub` line, where it reads the endsub.
        8,
        r#"N..... MESSAGE(" 7.000000 1.000000")
           N..... MESSAGE(" 0.000000 0.000000")"#,
    );
    assert!(err.to_string().contains("endsub"), "{err}");
}

/// read_named_parameter_setting defines `#<name>` (0) when it reads `#<name> =`, before the
/// value: the rest of the line reads it as 0.
#[test]
fn a_named_assignment_defines_the_name_for_its_line() {
    same(
        "G21\n#<a> = #<a> #<b> = [#<a> + 1]\n(DEBUG, #<a> #<b>)\n#<c> = 5 #<d> = #<c>\n\
         (DEBUG, #<c> #<d>)\nM2\n",
        r#"N..... MESSAGE(" 0.000000 1.000000")
           N..... MESSAGE(" 5.000000 0.000000")"#,
    );
    // rs274: "Named parameter #<f> not defined".
    stops_at("G21\n#<e> = #<f>\nM2\n", 2, "");
}

/// G33.1 prints as rs274's one `RIGID_TAP(x, y, z)` (the bottom of the tap), not as the moves
/// swarf makes it of; the tool is back where it started.
#[test]
fn rigid_tap_prints_as_rs274() {
    same(
        "G21 G0 X1 Y1 Z1\nS500 M3\nG33.1 X3 Z-2 K1\nG0 X2\nG20\nG33.1 Z-0.2 K0.1\nM2\n",
        "N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         N..... RIGID_TAP(3.0000, 1.0000, -2.0000)
         N..... STRAIGHT_TRAVERSE(2.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         N..... RIGID_TAP(0.0787, 0.0394, -0.2000)",
    );
}

/// convert_setup moves the current point into the changed active system without the G92
/// offset (unrotated by the old rotation, offsets swapped, rotated by the new one): with a G92
/// offset in effect a new rotation moves the program position as rs274 has it.
#[test]
fn g10_rotation_under_g92_moves_the_point_as_rs274() {
    same(
        "G21 G90 F100\nG0 X1 Y1\nG92 Y2.578\nG10 L2 P0 Y-17.290 R-60.93\n\
         (DEBUG, #<_x> #<_y> #5420 #5421)\nG1 X[#<_x>+1] Y[#<_y>]\nG1 X0 Y0\nM2\n",
        r#"N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)
           N..... MESSAGE(" -16.879286 10.527447 -16.879286 10.527447")
           N..... STRAIGHT_FEED(-15.8793, 10.5274, 0.0000, 0.0000, 0.0000, 0.0000)
           N..... STRAIGHT_FEED(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)"#,
    );
}

/// read_real_value refuses a value that is infinite or not a number.
#[test]
fn infinite_values_are_errors() {
    // rs274: "Calculation resulted in 'infinity'".
    stops_at("G21\n#1=0\n#2=[#1 ** -0.5]\nG0 X1\nM2\n", 3, "");
}

/// While rs274 skips a definition an undefined named parameter reads 0 (defining_sub), in
/// the endsub value it reads there too.
#[test]
fn undefined_names_read_zero_in_a_skipped_definition() {
    same(
        "G21\no<s> sub\no<s> endsub [#<nope> + 2]\n(DEBUG, #<_value> #<_value_returned>)\n\
         G0 X1\nM2\n",
        r#"N..... MESSAGE(" 2.000000 1.000000")
           N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)"#,
    );
}

/// rs274 evaluates every `elseif` of an if whose branch was taken on its way to the endif:
/// a condition that cannot be evaluated stops the program.
#[test]
fn elseif_conditions_after_a_taken_branch_are_evaluated() {
    // rs274: "Attempt to divide by zero" at the elseif, each time.
    stops_at(
        "G21\n#1=0\no1 if [1]\nG0 X1\no1 elseif [1/#1]\nG0 X2\no1 endif\nG0 X3\nM2\n",
        5,
        "N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    stops_at(
        "G21\n#1=0\no1 if [1]\nG0 X1\no1 elseif [0]\nG0 X2\no1 elseif [1/#1]\nG0 X2\no1 else\n\
         G0 X4\no1 endif\nG0 X3\nM2\n",
        7,
        "N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    stops_at(
        "G21\n#1=0\no1 if [0]\nG0 X1\no1 elseif [1]\nG0 X2\no1 elseif [1/#1]\nG0 X2\no1 else\n\
         G0 X4\no1 endif\nG0 X3\nM2\n",
        7,
        "N..... STRAIGHT_TRAVERSE(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// rs274's O-word offset table: one name per if/while/repeat in a call level (a `while` may
/// close its `do`; a subroutine's names are its own, for each call).
#[test]
fn o_names_are_not_reused_in_a_call_level() {
    // rs274: "5: duplicate O-word label - already defined in line 2: 'o100 if [1]'".
    let e = stops_at(
        "G21\no100 if [1]\nG0 X1\no100 endif\no100 if [1]\nG0 X2\no100 endif\nM2\n",
        5,
        "N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    assert!(e.to_string().contains("duplicate O-word label"), "{e}");
    same(
        "G21\no<s> sub\no100 if [1]\nG0 X1\no100 endif\no<s> endsub\no<s> call\no<s> call\n\
         o100 repeat [2]\nG0 X3\no100 endrepeat\no101 do\nG0 X4\no101 while [0]\nM2\n",
        "N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(3.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(3.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(4.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// rs274 2.9 changes units under cutter compensation; the move held for its corner prints in
/// the new units.
#[test]
fn units_change_under_compensation() {
    same(
        "G21 G17 F100\nG0 X0 Y0\nG41.1 D2\nG1 X10\nG20\nG1 X1\nG40\nG1 X2\nM2\n",
        "N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(0.3937, 0.0394, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(1.0000, 0.0394, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// check_other_codes: an R word nothing in its block uses is an error, an `R3` alone in a
/// canned cycle's mode too (swarf warned and went on with the cycle).
#[test]
fn an_r_word_alone_in_cycle_mode_is_an_error() {
    // rs274: "R word with no g code that uses it" at `R3`.
    stops_at(
        "G21 F100\nG0 Z5\nG81 X1 Y1 Z-1 R2\nR3\nX2\nG80\nM2\n",
        4,
        "N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 5.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(1.0000, 1.0000, -1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// `#<_abs_x>` … are the controlled point's machine position: rs274 adds the tool length
/// offset (the tool table's T2 is Z0.1 inch).
#[test]
fn abs_positions_include_the_tool_length_offset() {
    let opts = GcodeOptions::default()
        .with_parameter_units(Units::Inch)
        .with_tool_offsets(2, [0.0, 0.0, 2.54, 0.0, 0.0, 0.0]);
    let (out, err) = canonical(
        "G21\nG0 X1 Y2 Z3\nG43 H2\n(DEBUG, #<_abs_x> #<_abs_y> #<_abs_z> #<_z>)\n\
         G43.1 Z-1\n(DEBUG, #<_abs_z> #<_z>)\nM2\n",
        &opts,
    );
    assert!(err.is_none(), "{err:?}");
    assert_eq!(
        out,
        lines(
            r#"N..... STRAIGHT_TRAVERSE(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
               N..... MESSAGE(" 1.000000 2.000000 3.000000 0.460000")
               N..... MESSAGE(" 3.000000 4.000000")"#
        )
    );
}

/// Cutter compensation at the radius's own length, and the position after G40 and a tool
/// change (nc_files' useful-subroutines.ngc, which rs274 runs and swarf refused): an entry move
/// exactly as long as the tool radius and an arc the tool runs inside at exactly its radius are
/// taken (rs274's radius comes a rounding under the nominal one through its unit conversions;
/// swarf's millimetres compute the equality exactly), and a tool change right after G40
/// re-reads the position where the tool stands (rs274 ends the block, the task re-synchronises):
/// the `G0 Z` after it goes straight up from the compensated point.
#[test]
fn compensation_at_the_radius_and_the_position_after_a_change() {
    // T1: a 1/8 in end mill (simtbl's), radius 0.0625 in.
    let opts = GcodeOptions::default()
        .with_parameter_units(Units::Inch)
        .with_tool_diameter(1, 0.125 * 25.4);
    let src = "g20 g17 g90\nt1 m6\nf60\ng0 z.01\ng0 x.3125 y.125\ng41 g0 x.25 y.125\n\
               g3 x.25 y.125 i0 j-.0625\ng40\nt1 m6\ng0 z.02\nm2\n";
    let (out, err) = canonical(src, &opts);
    assert!(err.is_none(), "{err:?}");
    assert_eq!(
        out,
        lines(
            "N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.0100, 0.0000, 0.0000, 0.0000)
             N..... STRAIGHT_TRAVERSE(0.3125, 0.1250, 0.0100, 0.0000, 0.0000, 0.0000)
             N..... STRAIGHT_TRAVERSE(0.2500, 0.0625, 0.0100, 0.0000, 0.0000, 0.0000)
             N..... ARC_FEED(0.2500, 0.0625, 0.2500, 0.0625, 1, 0.0100, 0.0000, 0.0000, 0.0000)
             N..... STRAIGHT_TRAVERSE(0.2500, 0.0625, 0.0200, 0.0000, 0.0000, 0.0000)"
        )
    );
}

/// rs274's `doing_break`: a `break` it reads sets it — also one it passes while skipping a
/// `while` whose condition ended it (the break's `if` never ran) — and only the end of a `do`
/// loop clears it, not looping back that once. So after a `while` loop with a `break` in it,
/// the next do-while loop runs once (LinuxCNC 2.9's interp_o_word.cc; found by differential
/// testing, 2 of 400 random programs). A `break` or `continue` naming a `repeat` is refused.
#[test]
fn a_break_in_a_while_loop_ends_the_next_do_loop_early() {
    // The break never runs: the while ends by its condition.
    same(
        "G21\n#43 = 0\no436 while [#43 LT 2]\n#43 = [#43 + 1]\no1436 if [0]\no436 break\n\
         o1436 endif\no436 endwhile\n#49 = 0\no946 do\n#49 = [#49 + 1]\n(debug,it #49)\n\
         o946 while [#49 LT 3]\nM2\n",
        "N..... MESSAGE(\"it 1.000000\")",
    );
    // The break runs: the next do loop runs once, the one after it as written.
    same(
        "G21\n#43 = 0\no436 while [#43 LT 5]\n#43 = [#43 + 1]\no1436 if [#43 EQ 2]\n\
         o436 break\no1436 endif\no436 endwhile\n#49 = 0\no946 do\n#49 = [#49 + 1]\n\
         (debug,it #49)\no946 while [#49 LT 3]\n#50 = 0\no947 do\n#50 = [#50 + 1]\n\
         (debug,again #50)\no947 while [#50 LT 2]\nM2\n",
        "N..... MESSAGE(\"it 1.000000\")
         N..... MESSAGE(\"again 1.000000\")
         N..... MESSAGE(\"again 2.000000\")",
    );
    // A do loop's own break is cleared at its end: the next do loop is whole.
    same(
        "G21\n#1 = 0\no1 do\n#1 = [#1 + 1]\no2 if [#1 EQ 2]\no1 break\no2 endif\n\
         o1 while [#1 LT 5]\n#3 = 0\no3 do\n#3 = [#3 + 1]\n(debug,d #3)\no3 while [#3 LT 2]\nM2\n",
        "N..... MESSAGE(\"d 1.000000\")
         N..... MESSAGE(\"d 2.000000\")",
    );
    // rs274: "no matching while/do label: 'o436 break' (found 'repeat' in line 2)", at the
    // break's line, also where the repeat's count skips its body.
    stops_at(
        "G21\no436 repeat [0]\no436 break\no436 endrepeat\nM2\n",
        3,
        "",
    );
    let e = stops_at(
        "G21\no1 repeat [2]\n(debug,r)\no1 continue\no1 endrepeat\nM2\n",
        4,
        "N..... MESSAGE(\"r\")",
    );
    assert!(e.message.contains("repeat"), "{e}");
}

/// The rest of rs274's `doing_break`, found by review: a do loop's end clears it even when it
/// does not loop back (its condition false, or a break out of it, after which rs274 still
/// reads the closing `while`), and a `continue` reads the breaks of its loop's name on its way
/// to the loop's end, so one in an `if` that never runs still ends a do loop there.
#[test]
fn a_do_loops_end_clears_the_break_and_a_continue_reads_breaks() {
    // (T1 is simtbl's 1/8 in end mill.)
    let opts = GcodeOptions::default()
        .with_parameter_units(Units::Inch)
        .with_tool_diameter(1, 0.125 * 25.4);
    let same_with = |src: &str, expected: &str| {
        let (out, err) = canonical(src, &opts);
        assert!(err.is_none(), "{err:?}");
        assert_eq!(out, lines(expected));
    };
    let three = "N..... STRAIGHT_FEED(1.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)
                 N..... STRAIGHT_FEED(2.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)
                 N..... STRAIGHT_FEED(3.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)";
    same_with(
        "G20 G17 G90 G94\no1 while [1]\n o1 break\no1 endwhile\no2 do\n G1 X1 F10\no2 while [0]\n\
         #1=0\no3 do\n #1=[#1+1]\n G1 X#1 Y1\no3 while [#1 LT 3]\nM2\n",
        &format!("N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n{three}"),
    );
    same_with(
        "G20 G17 G90 G94 F10\no1 while [1]\n o1 break\no1 endwhile\no2 do\n G1 X1\n o2 break\n\
         o2 while [1]\n#3=0\no3 do\n #3=[#3+1]\n G1 X#3 Y1\no3 while [#3 LT 3]\nM2\n",
        &format!("N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n{three}"),
    );
    same_with(
        "G20 G17 G90 G94 F10\n#1=0\no1 do\n #1=[#1+1]\n o2 if [#1 EQ 2]\n  o1 continue\n o2 endif\n\
         G1 X#1\n o3 if [#1 GT 10]\n  o1 break\n o3 endif\no1 while [#1 LT 4]\nM2\n",
        "N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    // A move in the block of the tool change starts from the programmed point; the position is
    // re-read after the block.
    same_with(
        "G20 G17 G90 G94 F10\nT1 M6\nG0 X1 Y1\nG41 G1 X1 Y0.5\nG1 X1.5 Y0.5\nG40\nT2 M6 G1 X3\n\
         G1 Y2\nM2\n",
        "N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(1.0625, 0.5625, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(1.5000, 0.5625, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(3.0000, 0.5000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(3.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    // rs274: "The move just after exiting cutter compensation mode must be straight, not an
    // arc" — the change in between does not lift that.
    let (_, err) = canonical(
        "G20 G17 G90 G94 F10\nT1 M6\nG0 X1 Y1\nG41 G1 X1 Y0.5\nG1 X1.5 Y0.5\nG40\nT2 M6\n\
         G2 X3 Y0.5 R1\nM2\n",
        &opts,
    );
    assert_eq!(err.unwrap().pos.line, 8);
    // An R arc the tool runs inside at exactly a table radius is taken, as an I J one.
    same_with(
        "G20 G17 G90 G94 F10\nT1 M6\nG0 X0 Y1\nG41 G1 X0 Y0\nG1 X1 Y0\nG3 X1 Y0.125 R0.0625\n\
         G1 X0 Y0.125\nG40 G1 X0 Y1\nM2\n",
        "N..... STRAIGHT_TRAVERSE(0.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(0.0625, 0.0625, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(1.0000, 0.0625, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... ARC_FEED(1.0000, 0.0625, 1.0000, 0.0625, 1, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(-0.0000, 0.0625, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(0.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    // G41.1's D is taken as written: an entry of exactly its radius is refused ("Length of
    // cutter compensation entry move is not greater than the tool radius").
    let (_, err) = canonical(
        "G20 G17 G90 G94 F10\nG0 X0.3125 Y0.125\nG41.1 D0.125 G1 X0.25 Y0.125\nG1 X0 Y0.125\n\
         G40 G1 X0 Y1\nM2\n",
        &opts,
    );
    assert_eq!(err.unwrap().pos.line, 3);
}
