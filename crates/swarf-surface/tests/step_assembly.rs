//! STEP assembly placements: parts placed by `MAPPED_ITEM`s and by assembly occurrences
//! (`CONTEXT_DEPENDENT_SHAPE_REPRESENTATION` with an `ITEM_DEFINED_TRANSFORMATION`), nested
//! sub-assemblies, units per representation, and the placements that cannot be applied. Every
//! placed patch is checked against the part read alone with the motion applied by hand.

mod common;
use common::step::Step;

use swarf_geom::math::Vec3;
use swarf_surface::io::{step, ReadError};
use swarf_surface::{CompoundSurface, ParametricSurface, ReadNote, Surface};

impl Step {
    fn origin(&mut self) -> u64 {
        self.axis([0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    }

    /// A part whose geometry (`faces`, made by the closure) is in a
    /// MANIFOLD_SURFACE_SHAPE_REPRESENTATION related to the part's SHAPE_REPRESENTATION (no
    /// transformation), with its product definition: `(shape representation, origin axis,
    /// product definition)`.
    fn part(&mut self, ctx: u64, faces: impl FnOnce(&mut Step) -> Vec<u64>) -> (u64, u64, u64) {
        let origin = self.origin();
        let faces = faces(self);
        let list = ids(&faces);
        let shell = self.add(format!("OPEN_SHELL('',({list}))"));
        let model = self.add(format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
        let geom = self.add(format!(
            "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('geom',(#{origin},#{model}),#{ctx})"
        ));
        let rep = self.add(format!("SHAPE_REPRESENTATION('part',(#{origin}),#{ctx})"));
        self.add(format!(
            "SHAPE_REPRESENTATION_RELATIONSHIP('','',#{rep},#{geom})"
        ));
        let pd = self.product(rep);
        (rep, origin, pd)
    }

    fn product(&mut self, rep: u64) -> u64 {
        let pd = self.add("PRODUCT_DEFINITION('design','',$,$)");
        let pds = self.add(format!("PRODUCT_DEFINITION_SHAPE('','',#{pd})"));
        self.add(format!("SHAPE_DEFINITION_REPRESENTATION(#{pds},#{rep})"));
        pd
    }

    /// A biquadratic B-spline face named `skin`.
    fn bspline_face(&mut self) -> u64 {
        let mut rows = Vec::new();
        for (i, zs) in ZS.iter().enumerate() {
            let mut row = Vec::new();
            for (j, z) in zs.iter().enumerate() {
                row.push(self.point([10.0 * i as f64, 8.0 * j as f64 + 0.5 * i as f64, *z]));
            }
            rows.push(format!("({})", ids(&row)));
        }
        let s = self.add(format!(
            "B_SPLINE_SURFACE_WITH_KNOTS('',2,2,({}),.UNSPECIFIED.,.F.,.F.,.F.,(3,3),(3,3),\
             (0.,1.),(0.,1.),.UNSPECIFIED.)",
            rows.join(",")
        ));
        self.add(format!("ADVANCED_FACE('skin',(),#{s},.T.)"))
    }

    /// A plane face `lid` trimmed by a square POLY_LOOP, and a cylinder face `wall` without
    /// bounds (its height takes the default range, with a note).
    fn elementary_faces(&mut self) -> Vec<u64> {
        let a = self.axis([5.0, 5.0, 2.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let plane = self.add(format!("PLANE('',#{a})"));
        let corners: Vec<u64> = [[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [0.0, 10.0]]
            .iter()
            .map(|c| self.point([c[0], c[1], 2.0]))
            .collect();
        let l = self.add(format!("POLY_LOOP('',({}))", ids(&corners)));
        let b = self.add(format!("FACE_OUTER_BOUND('',#{l},.T.)"));
        let lid = self.add(format!("ADVANCED_FACE('lid',(#{b}),#{plane},.T.)"));
        let c = self.axis([1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]);
        let cyl = self.add(format!("CYLINDRICAL_SURFACE('',#{c},4.)"));
        let wall = self.add(format!("ADVANCED_FACE('wall',(),#{cyl},.T.)"));
        vec![lid, wall]
    }

    /// Places `child` (with its `child_axis`) in `parent` at `at` by an assembly occurrence:
    /// `(REPRESENTATION_RELATIONSHIP(child, parent) …WITH_TRANSFORMATION(
    /// ITEM_DEFINED_TRANSFORMATION(child_axis, at)))` (or written the other way round, parent
    /// first and the transformation inverted, when `reversed`); the occurrence's number.
    fn occurrence(
        &mut self,
        parent: (u64, u64),
        child: (u64, u64),
        child_axis: u64,
        at: u64,
        reversed: bool,
    ) -> u64 {
        let (parent_rep, parent_pd) = parent;
        let (child_rep, child_pd) = child;
        let nauo = self.add(format!(
            "NEXT_ASSEMBLY_USAGE_OCCURRENCE('o','o','',#{parent_pd},#{child_pd},$)"
        ));
        let pds = self.add(format!("PRODUCT_DEFINITION_SHAPE('','',#{nauo})"));
        let (r1, r2, i1, i2) = if reversed {
            (parent_rep, child_rep, at, child_axis)
        } else {
            (child_rep, parent_rep, child_axis, at)
        };
        let t = self.add(format!("ITEM_DEFINED_TRANSFORMATION('','',#{i1},#{i2})"));
        let rel = self.add(format!(
            "( REPRESENTATION_RELATIONSHIP('','',#{r1},#{r2}) \
             REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#{t}) \
             SHAPE_REPRESENTATION_RELATIONSHIP() )"
        ));
        self.add(format!(
            "CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#{rel},#{pds})"
        ));
        nauo
    }

    /// Adds `item` to the items of representation `rep`.
    fn hold(&mut self, rep: u64, item: u64) {
        let l = &mut self.lines[rep as usize - 1];
        *l = l.replacen("',(", &format!("',(#{item},"), 1);
    }

    /// A MAPPED_ITEM of `rep` from `origin` onto `target`; its number.
    fn mapped(&mut self, origin: u64, rep: u64, target: u64) -> u64 {
        let map = self.add(format!("REPRESENTATION_MAP(#{origin},#{rep})"));
        self.add(format!("MAPPED_ITEM('',#{map},#{target})"))
    }
}

const ZS: [[f64; 3]; 3] = [[0.0, 1.0, 0.0], [2.0, 3.0, 1.0], [0.0, 1.0, 2.0]];

fn ids(v: &[u64]) -> String {
    v.iter()
        .map(|i| format!("#{i}"))
        .collect::<Vec<_>>()
        .join(",")
}

/// The part read alone, in its own frame.
fn alone(faces: impl FnOnce(&mut Step) -> Vec<u64>) -> CompoundSurface {
    let mut s = Step::default();
    let ctx = s.context(false);
    s.part(ctx, faces);
    let r = s.parse();
    assert!(
        !r.notes.iter().any(|n| matches!(
            n,
            ReadNote::PlacementsApplied { .. } | ReadNote::PlacementNotApplied { .. }
        )),
        "{:?}",
        r.notes
    );
    r
}

/// `placed` is `own` moved by `m`: points over a 7 × 7 grid of the parameter box agree to 1e-9
/// relative, and the parameter boxes and trims are the same.
fn assert_moved(
    placed: &swarf_surface::Patch,
    own: &swarf_surface::Patch,
    m: &dyn Fn(Vec3) -> Vec3,
) {
    let d = own.surface.domain();
    assert_eq!(placed.surface.domain(), d, "{:?}", placed.name);
    assert_eq!(placed.trim, own.trim);
    assert_eq!(placed.flipped, own.flipped);
    assert_eq!(placed.surface.kind(), own.surface.kind());
    for i in 0..7 {
        for j in 0..7 {
            let (u, v) = (d.u_at(i as f64 / 6.0), d.v_at(j as f64 / 6.0));
            let want = m(own.surface.point(u, v));
            let got = placed.surface.point(u, v);
            assert!(
                (got - want).length() <= 1e-9 * (1.0 + want.length()),
                "{:?} at ({u}, {v}): {got} vs {want}",
                placed.name
            );
        }
    }
}

fn rot_z90(p: Vec3) -> Vec3 {
    Vec3::new(-p.y, p.x, p.z)
}

fn applied(s: &CompoundSurface) -> Option<(usize, usize)> {
    s.notes.iter().find_map(|n| match n {
        ReadNote::PlacementsApplied { instances, parts } => Some((*instances, *parts)),
        _ => None,
    })
}

fn not_applied(s: &CompoundSurface) -> Vec<String> {
    s.notes
        .iter()
        .filter(|n| matches!(n, ReadNote::PlacementNotApplied { .. }))
        .map(ToString::to_string)
        .collect()
}

#[test]
fn a_bspline_part_used_twice_is_read_once_per_placement() {
    // One B-spline part in an assembly twice: translated by (100, 0, 0), and turned 90° about
    // Z and moved to (0, 50, 10). Each placed patch is the part's own patch moved by its
    // placement, whichever way round the relationships are written (component first, as CAD
    // systems write them, or assembly first with the transformation inverted: the assembly
    // occurrences say which is which).
    let own = alone(|s| vec![s.bspline_face()]);
    let own = &own.patches[0];
    for reversed in [false, true] {
        let mut s = Step::default();
        let ctx = s.context(false);
        let (part, part_axis, part_pd) = s.part(ctx, |s| vec![s.bspline_face()]);
        let a1 = s.axis([100.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let a2 = s.axis([0.0, 50.0, 10.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]);
        let asm_axis = s.origin();
        let asm = s.add(format!(
            "SHAPE_REPRESENTATION('assy',(#{asm_axis},#{a1},#{a2}),#{ctx})"
        ));
        let asm_pd = s.product(asm);
        let o1 = s.occurrence((asm, asm_pd), (part, part_pd), part_axis, a1, reversed);
        let o2 = s.occurrence((asm, asm_pd), (part, part_pd), part_axis, a2, reversed);
        let r = s.parse();
        assert_eq!(r.patches.len(), 2, "{:?}", r.notes);
        assert_eq!(applied(&r), Some((2, 1)), "{:?}", r.notes);
        assert!(not_applied(&r).is_empty(), "{:?}", r.notes);
        let names: Vec<_> = r.patches.iter().map(|p| p.name.clone().unwrap()).collect();
        assert_eq!(names, [format!("skin@#{o1}"), format!("skin@#{o2}")]);
        assert_moved(&r.patches[0], own, &|p| p + Vec3::new(100.0, 0.0, 0.0));
        assert_moved(&r.patches[1], own, &|p| {
            rot_z90(p) + Vec3::new(0.0, 50.0, 10.0)
        });
        let note = r
            .notes
            .iter()
            .find(|n| matches!(n, ReadNote::PlacementsApplied { .. }))
            .unwrap()
            .to_string();
        assert!(note.contains("2 placed instance(s) of 1 part(s)"), "{note}");
    }
}

#[test]
fn elementary_faces_placed_by_a_mapped_item_keep_their_parameters_and_trims() {
    // A trimmed plane and a cylinder, mapped from an origin at (1, 2, 3) onto a target at
    // (10, 20, 30) whose z axis is +X and x axis +Y: p ↦ R·(p − (1, 2, 3)) + (10, 20, 30) with
    // R(a, b, c) = (c, a, b). The trims, the parameter boxes and the per-patch notes (the
    // trim, the cylinder's default height range) are the part's.
    let own = alone(|s| s.elementary_faces());
    let mut s = Step::default();
    let ctx = s.context(false);
    let (part, _, _) = s.part(ctx, |s| s.elementary_faces());
    let from = s.axis([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let to = s.axis([10.0, 20.0, 30.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let m = s.mapped(from, part, to);
    s.add(format!("SHAPE_REPRESENTATION('assy',(#{m}),#{ctx})"));
    let r = s.parse();
    assert_eq!(applied(&r), Some((1, 1)), "{:?}", r.notes);
    assert!(not_applied(&r).is_empty(), "{:?}", r.notes);
    assert_eq!(r.patches.len(), 2);
    let m = |p: Vec3| {
        let q = p - Vec3::new(1.0, 2.0, 3.0);
        Vec3::new(q.z, q.x, q.y) + Vec3::new(10.0, 20.0, 30.0)
    };
    for (placed, own) in r.patches.iter().zip(&own.patches) {
        assert_eq!(placed.name, own.name, "one instance: names unchanged");
        assert_moved(placed, own, &m);
    }
    assert!(r.patches[0].trim.is_some());
    let Surface::Cylinder(c) = &r.patches[1].surface else {
        panic!()
    };
    assert!(
        (c.frame.z - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-15,
        "{:?}",
        c.frame
    );
    assert!((c.frame.origin - m(Vec3::new(1.0, 2.0, 0.0))).length() < 1e-12);
    assert_eq!(c.radius, 4.0);
    let per_patch = |s: &CompoundSurface| {
        s.notes
            .iter()
            .filter(|n| {
                matches!(
                    n,
                    ReadNote::Trimmed { .. } | ReadNote::DefaultParameterBox { .. }
                )
            })
            .cloned()
            .collect::<Vec<_>>()
    };
    assert_eq!(per_patch(&r), per_patch(&own));
}

#[test]
fn an_export_shaped_file_places_each_face_once() {
    // As CAD systems write it: the geometry's representation first in its relationship to the
    // product's shape representation, the faces also reached by styled items of a
    // presentation representation (which places nothing), the part placed once in the
    // assembly. One patch, placed, named as the face (a single instance), and no other note
    // about placements.
    let own = alone(|s| vec![s.bspline_face()]);
    let mut s = Step::default();
    let ctx = s.context(false);
    let origin = s.origin();
    let face = s.bspline_face();
    let shell = s.add(format!("OPEN_SHELL('',(#{face}))"));
    let model = s.add(format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
    let geom = s.add(format!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#{origin},#{model}),#{ctx})"
    ));
    let part = s.add(format!("SHAPE_REPRESENTATION('part',(#{origin}),#{ctx})"));
    s.add(format!(
        "SHAPE_REPRESENTATION_RELATIONSHIP('','',#{geom},#{part})"
    ));
    let part_pd = s.product(part);
    let colour = s.add("COLOUR_RGB('',0.5,0.5,0.5)");
    let styled = s.add(format!("STYLED_ITEM('',(#{colour}),#{face})"));
    let styled_model = s.add(format!("STYLED_ITEM('',(#{colour}),#{model})"));
    s.add(format!(
        "MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION('',(#{styled},#{styled_model}),#{ctx})"
    ));
    let at = s.axis([0.0, 0.0, -30.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]);
    let asm_origin = s.origin();
    let asm = s.add(format!(
        "SHAPE_REPRESENTATION('assy',(#{asm_origin},#{at}),#{ctx})"
    ));
    let asm_pd = s.product(asm);
    s.occurrence((asm, asm_pd), (part, part_pd), origin, at, false);
    let r = s.parse();
    assert_eq!(r.patches.len(), 1, "{:?}", r.notes);
    assert_eq!(r.patches[0].name.as_deref(), Some("skin"));
    assert_eq!(applied(&r), Some((1, 1)), "{:?}", r.notes);
    assert!(not_applied(&r).is_empty(), "{:?}", r.notes);
    assert_moved(&r.patches[0], &own.patches[0], &|p| {
        rot_z90(p) + Vec3::new(0.0, 0.0, -30.0)
    });
}

#[test]
fn nested_sub_assemblies_compose_their_placements() {
    // A sub-assembly holds the part twice by MAPPED_ITEMs (at (5, 0, 0), and turned 90° about
    // Z at (0, 0, 7)); the top assembly holds the sub-assembly twice by assembly occurrences
    // (at (0, 0, 100), and turned 90° about X at (200, 0, 0)). Four instances, each the
    // composition top ∘ sub applied to the part.
    let own = alone(|s| vec![s.bspline_face()]);
    let own = &own.patches[0];
    let mut s = Step::default();
    let ctx = s.context(false);
    let (part, part_axis, _) = s.part(ctx, |s| vec![s.bspline_face()]);
    let t1 = s.axis([5.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let t2 = s.axis([0.0, 0.0, 7.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]);
    let m1 = s.mapped(part_axis, part, t1);
    let m2 = s.mapped(part_axis, part, t2);
    let sub_axis = s.origin();
    let sub = s.add(format!(
        "SHAPE_REPRESENTATION('sub',(#{sub_axis},#{m1},#{m2}),#{ctx})"
    ));
    let sub_pd = s.product(sub);
    let u1 = s.axis([0.0, 0.0, 100.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    // Turned 90° about X: y → z, z → −y.
    let u2 = s.axis([200.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]);
    let top_axis = s.origin();
    let top = s.add(format!(
        "SHAPE_REPRESENTATION('top',(#{top_axis},#{u1},#{u2}),#{ctx})"
    ));
    let top_pd = s.product(top);
    let o1 = s.occurrence((top, top_pd), (sub, sub_pd), sub_axis, u1, false);
    let o2 = s.occurrence((top, top_pd), (sub, sub_pd), sub_axis, u2, false);
    let r = s.parse();
    assert_eq!(applied(&r), Some((4, 1)), "{:?}", r.notes);
    assert!(not_applied(&r).is_empty(), "{:?}", r.notes);
    assert_eq!(r.patches.len(), 4);
    let subs: [&dyn Fn(Vec3) -> Vec3; 2] = [&|p| p + Vec3::new(5.0, 0.0, 0.0), &|p| {
        rot_z90(p) + Vec3::new(0.0, 0.0, 7.0)
    }];
    let tops: [&dyn Fn(Vec3) -> Vec3; 2] = [&|p| p + Vec3::new(0.0, 0.0, 100.0), &|p| {
        Vec3::new(p.x, -p.z, p.y) + Vec3::new(200.0, 0.0, 0.0)
    }];
    let mut k = 0;
    for (o, top) in [o1, o2].into_iter().zip(tops) {
        for (m, sub) in [m1, m2].into_iter().zip(subs) {
            let p = &r.patches[k];
            assert_eq!(p.name.as_deref(), Some(format!("skin@#{o}/#{m}").as_str()));
            assert_moved(p, own, &|q| top(sub(q)));
            k += 1;
        }
    }
}

#[test]
fn placements_are_read_in_each_representation_s_units() {
    // The part in inches, the assembly in millimetres: the part's origin item at (1, 0, 0) in,
    // the assembly's at (100, 0, 0) mm: the part moves by 100 − 25.4 mm along x.
    let own = alone(|s| vec![s.bspline_face()]);
    let own = &own.patches[0];
    let mut s = Step::default();
    let inch = s.context(true);
    let mm = s.context(false);
    let (part, _, part_pd) = s.part(inch, |s| vec![s.bspline_face()]);
    let from = s.axis([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let at = s.axis([100.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let asm = s.add(format!("SHAPE_REPRESENTATION('assy',(#{at}),#{mm})"));
    let asm_pd = s.product(asm);
    s.occurrence((asm, asm_pd), (part, part_pd), from, at, false);
    let r = s.parse();
    assert_eq!(applied(&r), Some((1, 1)), "{:?}", r.notes);
    assert_moved(&r.patches[0], own, &|p| {
        p * 25.4 + Vec3::new(100.0 - 25.4, 0.0, 0.0)
    });
}

#[test]
fn a_single_part_reads_as_before() {
    // A part with its product structure (shape representation, geometry representation, the
    // relationship between them, product definition) and the same faces bare: the same
    // patches and notes, and no placement note. (A regression guard: the reader read it so
    // before placements were applied.)
    let mut bare = Step::default();
    bare.context(false);
    bare.origin();
    let faces = {
        let mut v = vec![bare.bspline_face()];
        v.extend(bare.elementary_faces());
        v
    };
    let list = ids(&faces);
    bare.add(format!("OPEN_SHELL('',({list}))"));
    let mut full = Step::default();
    let ctx = full.context(false);
    full.part(ctx, |s| {
        let mut v = vec![s.bspline_face()];
        v.extend(s.elementary_faces());
        v
    });
    let (a, b) = (bare.parse(), full.parse());
    assert_eq!(a.patches.len(), 3);
    for (p, q) in a.patches.iter().zip(&b.patches) {
        assert_eq!(p.name, q.name);
        assert_eq!(p.surface, q.surface);
        assert_eq!(p.trim, q.trim);
    }
    assert_eq!(a.notes, b.notes);
    assert!(applied(&b).is_none() && not_applied(&b).is_empty());
}

#[test]
fn cycles_and_broken_placements_are_noted_not_followed() {
    // (a) A places B, B places A, nothing above them: no root reaches them; both placements
    // are noted and the faces are read in their own frame.
    let own = alone(|s| vec![s.bspline_face()]);
    let own = &own.patches[0];
    let mut s = Step::default();
    let ctx = s.context(false);
    let (b, b_axis, _) = s.part(ctx, |s| vec![s.bspline_face()]);
    let a_axis = s.origin();
    let t = s.axis([9.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let a = s.add(format!("SHAPE_REPRESENTATION('a',(#{a_axis}),#{ctx})"));
    let to_b = s.mapped(b_axis, b, t);
    let to_a = s.mapped(a_axis, a, t);
    s.hold(a, to_b);
    s.hold(b, to_a);
    let r = s.parse();
    assert_eq!(r.patches.len(), 1, "{:?}", r.notes);
    assert_moved(&r.patches[0], own, &|p| p);
    let notes = not_applied(&r);
    assert!(
        notes.iter().any(|n| n.contains("cycle of placements")),
        "{notes:?}"
    );

    // (b) A root reaching a cycle: root → A → B → A. The placement back to A is noted; the
    // faces get the root's chain only.
    let mut s = Step::default();
    let ctx = s.context(false);
    let (b, b_axis, _) = s.part(ctx, |s| vec![s.bspline_face()]);
    let a_axis = s.origin();
    let t = s.axis([9.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let a = s.add(format!("SHAPE_REPRESENTATION('a',(#{a_axis}),#{ctx})"));
    let to_b = s.mapped(b_axis, b, t);
    let to_a = s.mapped(a_axis, a, t);
    s.hold(a, to_b);
    s.hold(b, to_a);
    let root_map = s.mapped(a_axis, a, t);
    s.add(format!("SHAPE_REPRESENTATION('root',(#{root_map}),#{ctx})"));
    let r = s.parse();
    // B is a child of A, which is a child of the root and of B: root → A → B, 18 mm along x.
    assert_eq!(r.patches.len(), 1, "{:?}", r.notes);
    assert_moved(&r.patches[0], own, &|p| p + Vec3::new(18.0, 0.0, 0.0));
    let notes = not_applied(&r);
    assert!(
        notes
            .iter()
            .any(|n| n.contains(&format!("MAPPED_ITEM #{to_a}")) && n.contains("inside itself")),
        "{notes:?}"
    );

    // (c) Broken placements: an ITEM_DEFINED_TRANSFORMATION whose item is a point, a mapped
    // item whose map is not defined, a mirroring operator. Each is noted by name; the part is
    // read unmoved by it; nothing panics.
    let mut s = Step::default();
    let ctx = s.context(false);
    let (part, part_axis, part_pd) = s.part(ctx, |s| vec![s.bspline_face()]);
    let pt = s.point([1.0, 1.0, 1.0]);
    let asm = s.add(format!(
        "SHAPE_REPRESENTATION('assy',(#{part_axis}),#{ctx})"
    ));
    let asm_pd = s.product(asm);
    let o = s.occurrence((asm, asm_pd), (part, part_pd), pt, part_axis, false);
    let r = s.parse();
    let notes = not_applied(&r);
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].contains("ITEM_DEFINED_TRANSFORMATION")
            && notes[0].contains("not an AXIS2_PLACEMENT_3D"),
        "{notes:?}"
    );
    assert_moved(&r.patches[0], own, &|p| p);
    let _ = o;

    let mut s = Step::default();
    let ctx = s.context(false);
    let (_, _, _) = s.part(ctx, |s| vec![s.bspline_face()]);
    let m = s.add("MAPPED_ITEM('',#999,#1)");
    s.add(format!("SHAPE_REPRESENTATION('assy',(#{m}),#{ctx})"));
    let r = s.parse();
    let notes = not_applied(&r);
    assert!(
        notes
            .iter()
            .any(|n| n.contains(&format!("MAPPED_ITEM #{m}")) && n.contains("cannot be resolved")),
        "{notes:?}"
    );
    assert_moved(&r.patches[0], own, &|p| p);

    let mut s = Step::default();
    let ctx = s.context(false);
    let (part, part_axis, _) = s.part(ctx, |s| vec![s.bspline_face()]);
    let o = s.point([0.0, 0.0, 0.0]);
    let x = s.add("DIRECTION('',(1.,0.,0.))");
    let y = s.add("DIRECTION('',(0.,-1.,0.))");
    let z = s.add("DIRECTION('',(0.,0.,1.))");
    let op = s.add(format!(
        "CARTESIAN_TRANSFORMATION_OPERATOR_3D('',#{x},#{y},#{o},1.,#{z})"
    ));
    let m = s.mapped(part_axis, part, op);
    s.add(format!("SHAPE_REPRESENTATION('assy',(#{m}),#{ctx})"));
    let r = s.parse();
    let notes = not_applied(&r);
    assert!(
        notes
            .iter()
            .any(|n| n.contains(&format!("MAPPED_ITEM #{m}")) && n.contains("mirrors")),
        "{notes:?}"
    );
    assert_moved(&r.patches[0], own, &|p| p);
}

#[test]
fn a_scaling_operator_scales_surfaces_parameters_and_trims() {
    // A CARTESIAN_TRANSFORMATION_OPERATOR_3D with scale 2 and a quarter turn about Z, origin
    // (3, 4, 5): the B-spline's points and the plane's and cylinder's (whose linear parameters
    // and trim double).
    let own = alone(|s| {
        let mut v = vec![s.bspline_face()];
        v.extend(s.elementary_faces());
        v
    });
    let mut s = Step::default();
    let ctx = s.context(false);
    let (part, part_axis, _) = s.part(ctx, |s| {
        let mut v = vec![s.bspline_face()];
        v.extend(s.elementary_faces());
        v
    });
    let o = s.point([3.0, 4.0, 5.0]);
    let x = s.add("DIRECTION('',(0.,1.,0.))");
    let op = s.add(format!(
        "CARTESIAN_TRANSFORMATION_OPERATOR_3D('',#{x},$,#{o},2.,$)"
    ));
    let m = s.mapped(part_axis, part, op);
    s.add(format!("SHAPE_REPRESENTATION('assy',(#{m}),#{ctx})"));
    let r = s.parse();
    assert_eq!(applied(&r), Some((1, 1)), "{:?}", r.notes);
    assert!(not_applied(&r).is_empty(), "{:?}", r.notes);
    let m = |p: Vec3| rot_z90(p) * 2.0 + Vec3::new(3.0, 4.0, 5.0);
    // The B-spline: same parameters.
    assert_moved(&r.patches[0], &own.patches[0], &m);
    // Plane (u, v doubled) and cylinder (v doubled).
    for (k, su, sv) in [(1, 2.0, 2.0), (2, 1.0, 2.0)] {
        let (p, q) = (&r.patches[k], &own.patches[k]);
        let d = q.surface.domain();
        let e = p.surface.domain();
        assert_eq!(e.u, [d.u[0] * su, d.u[1] * su]);
        assert_eq!(e.v, [d.v[0] * sv, d.v[1] * sv]);
        for i in 0..5 {
            for j in 0..5 {
                let (u, v) = (d.u_at(i as f64 / 4.0), d.v_at(j as f64 / 4.0));
                let want = m(q.surface.point(u, v));
                let got = p.surface.point(u * su, v * sv);
                assert!((got - want).length() <= 1e-9 * (1.0 + want.length()));
                if let (Some(a), Some(b)) = (&p.trim, &q.trim) {
                    assert_eq!(a.contains(u * su, v * sv), b.contains(u, v));
                }
            }
        }
    }
    assert!(r.patches[1].trim.is_some());
}

#[test]
fn an_absurd_number_of_instances_is_refused_clearly() {
    // 20 levels, each holding the level below twice: 2^20 instances.
    let mut s = Step::default();
    let ctx = s.context(false);
    let (mut rep, mut axis, _) = s.part(ctx, |s| vec![s.bspline_face()]);
    let t = s.axis([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    for _ in 0..20 {
        let m1 = s.mapped(axis, rep, t);
        let m2 = s.mapped(axis, rep, axis);
        axis = s.origin();
        rep = s.add(format!(
            "SHAPE_REPRESENTATION('level',(#{axis},#{m1},#{m2}),#{ctx})"
        ));
    }
    match step::parse(&s.text()) {
        Err(ReadError::Entity { message, .. }) => {
            assert!(message.contains("more than 100000 instances"), "{message}")
        }
        other => panic!("{other:?}"),
    }
    // 70 levels of one instance each: the walk stops at 64 with a note; the part, which it
    // does not reach, is read in its own frame.
    let mut s = Step::default();
    let ctx = s.context(false);
    let (mut rep, mut axis, _) = s.part(ctx, |s| vec![s.bspline_face()]);
    for _ in 0..70 {
        let m = s.mapped(axis, rep, axis);
        axis = s.origin();
        rep = s.add(format!(
            "SHAPE_REPRESENTATION('level',(#{axis},#{m}),#{ctx})"
        ));
    }
    let r = s.parse();
    assert_eq!(r.patches.len(), 1);
    assert!(applied(&r).is_none());
    let notes = not_applied(&r);
    assert!(
        notes.iter().any(|n| n.contains("nest more than 64 levels")),
        "{notes:?}"
    );
}

/// `levels` levels of `fan` mapped items each above the part made by `faces`: `fan^levels`
/// placed instances of it.
fn fanned(levels: usize, fan: usize, faces: impl FnOnce(&mut Step) -> Vec<u64>) -> Step {
    let mut s = Step::default();
    let ctx = s.context(false);
    let (mut rep, mut axis, _) = s.part(ctx, faces);
    for level in 0..levels {
        let mut items = vec![];
        for k in 0..fan {
            let at = [20.0 * (k * (level + 1)) as f64, 30.0 * k as f64, 0.0];
            let t = s.axis(at, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
            items.push(s.mapped(axis, rep, t));
        }
        axis = s.origin();
        rep = s.add(format!(
            "SHAPE_REPRESENTATION('level',(#{axis},{}),#{ctx})",
            ids(&items)
        ));
    }
    s
}

/// A bilinear B-spline face `net` of `n`×`n` control points over 10 × 10 mm.
fn net_face(s: &mut Step, n: usize) -> u64 {
    let mut rows = Vec::new();
    for i in 0..n {
        let row: Vec<u64> = (0..n)
            .map(|j| {
                let (x, y) = (
                    10.0 * i as f64 / (n - 1) as f64,
                    10.0 * j as f64 / (n - 1) as f64,
                );
                s.point([x, y, (i + j) as f64 % 2.0])
            })
            .collect();
        rows.push(format!("({})", ids(&row)));
    }
    let knots: Vec<String> = (0..n).map(|k| format!("{k}.")).collect();
    let mult: Vec<&str> = (0..n)
        .map(|k| if k == 0 || k == n - 1 { "2" } else { "1" })
        .collect();
    let (m, k) = (mult.join(","), knots.join(","));
    let surface = s.add(format!(
        "B_SPLINE_SURFACE_WITH_KNOTS('',1,1,({}),.UNSPECIFIED.,.F.,.F.,.F.,({m}),({m}),({k}),\
         ({k}),.UNSPECIFIED.)",
        rows.join(",")
    ));
    s.add(format!("ADVANCED_FACE('net',(),#{surface},.T.)"))
}

#[test]
fn placed_instances_copying_too_many_control_points_are_refused_before_the_copies() {
    // The reviewer's mk18.py in small: a face of 40×40 control points in 7 levels of 4
    // mapped items, 16 384 instances (under the 100 000 instances and the 500 000 patches):
    // 26 214 400 control points to copy, past the 2 million. Refused at the face, before any
    // copy (the walk only counts), naming the cap and what to do.
    let s = fanned(7, 4, |s| vec![net_face(s, 40)]);
    let face = s
        .lines
        .iter()
        .position(|l| l.starts_with("ADVANCED_FACE('net'"))
        .unwrap() as u64
        + 1;
    match step::parse(&s.text()) {
        Err(ReadError::Entity {
            entity, message, ..
        }) => {
            assert_eq!(entity, format!("#{face}"));
            assert!(
                message.starts_with(
                    "placed 16384 times by the assembly, its 1600 control points take the \
                     file's placed patches past 2000000 control points"
                ),
                "{message}"
            );
            assert!(
                message.contains(
                    "read the parts on their own, or export the assembly with fewer instances"
                ),
                "{message}"
            );
        }
        Err(e) => panic!("{e}"),
        Ok(r) => panic!("read {} patches", r.patches.len()),
    }
    // 4 levels, 256 instances, 409 600 control points: read, one patch per instance.
    let r = fanned(4, 4, |s| vec![net_face(s, 40)]).parse();
    assert_eq!(r.patches.len(), 256);
    assert_eq!(applied(&r), Some((256, 1)));
}

#[test]
fn placed_instances_copying_too_many_trim_points_are_refused_before_the_copies() {
    // A plane face bounded by a circle of radius 1 m: its trim, copied to each of 4^8 = 65 536
    // instances (87 381 with the levels', under the 100 000), would be past the 50 million
    // trim points.
    let disc = |s: &mut Step| {
        let a = s.axis([0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let plane = s.add(format!("PLANE('',#{a})"));
        let circle = s.add(format!("CIRCLE('',#{a},1000.)"));
        let p = s.point([1000.0, 0.0, 0.0]);
        let v = s.add(format!("VERTEX_POINT('',#{p})"));
        let e = s.add(format!("EDGE_CURVE('',#{v},#{v},#{circle},.T.)"));
        let oe = s.add(format!("ORIENTED_EDGE('',*,*,#{e},.T.)"));
        let l = s.add(format!("EDGE_LOOP('',(#{oe}))"));
        let b = s.add(format!("FACE_OUTER_BOUND('',#{l},.T.)"));
        vec![s.add(format!("ADVANCED_FACE('disc',(#{b}),#{plane},.T.)"))]
    };
    let one = alone(disc);
    let points: usize = one.patches[0]
        .trim
        .as_ref()
        .unwrap()
        .loops()
        .iter()
        .map(Vec::len)
        .sum();
    assert!(points * 65_536 > 50_000_000, "{points}");
    match step::parse(&fanned(8, 4, disc).text()) {
        Err(ReadError::Entity { message, .. }) => assert!(
            message.starts_with(&format!(
                "placed 65536 times by the assembly, its {points} trim points take the file's \
                 placed patches past 50000000 trim points"
            )),
            "{message}"
        ),
        Err(e) => panic!("{e}"),
        Ok(r) => panic!("read {} patches", r.patches.len()),
    }
}

#[test]
fn an_axis_along_x_without_a_reference_direction_takes_y_as_iso_10303_42_says() {
    // ISO 10303-42's first_proj_axis: with the reference direction omitted, x is (1, 0, 0)
    // made square to the axis, unless the axis is (1, 0, 0) or (−1, 0, 0): then (0, 1, 0). A
    // cylinder on such a placement: u = 0 at (0, 10, 0), u = π/2 at 10·(z × x).
    for (sign, y) in [(1.0, Vec3::Z), (-1.0, -Vec3::Z)] {
        let mut s = Step::default();
        s.context(false);
        let o = s.point([0.0; 3]);
        let z = s.add(format!("DIRECTION('',({sign:?},0.,0.))"));
        let a = s.add(format!("AXIS2_PLACEMENT_3D('',#{o},#{z},$)"));
        s.add(format!("CYLINDRICAL_SURFACE('c',#{a},10.)"));
        let r = s.parse();
        let c = &r.patches[0].surface;
        let (p0, p1) = (c.point(0.0, 0.0), c.point(std::f64::consts::FRAC_PI_2, 0.0));
        assert!(
            (p0 - Vec3::new(0.0, 10.0, 0.0)).length() < 1e-12,
            "{sign}: {p0}"
        );
        assert!((p1 - 10.0 * y).length() < 1e-12, "{sign}: {p1}");
    }
    // The same rule for a transformation operator (base_axis): axis3 −X, axis1 omitted gives
    // the axes (0, 1, 0), (0, 0, −1), (−1, 0, 0). It was refused as "axis1 parallel to axis3"
    // and the part read unplaced.
    let own = alone(|s| s.elementary_faces());
    let mut s = Step::default();
    let ctx = s.context(false);
    let (part, part_axis, _) = s.part(ctx, |s| s.elementary_faces());
    let o = s.point([3.0, 4.0, 5.0]);
    let z = s.add("DIRECTION('',(-1.,0.,0.))");
    let op = s.add(format!(
        "CARTESIAN_TRANSFORMATION_OPERATOR_3D('',$,$,#{o},1.,#{z})"
    ));
    let m = s.mapped(part_axis, part, op);
    s.add(format!("SHAPE_REPRESENTATION('assy',(#{m}),#{ctx})"));
    let r = s.parse();
    assert_eq!(applied(&r), Some((1, 1)), "{:?}", r.notes);
    assert!(not_applied(&r).is_empty(), "{:?}", r.notes);
    let m = |p: Vec3| Vec3::new(-p.z, p.x, -p.y) + Vec3::new(3.0, 4.0, 5.0);
    for k in 0..2 {
        assert_moved(&r.patches[k], &own.patches[k], &m);
    }
}
