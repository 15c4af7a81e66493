//! The machined part as a mesh: closed, outward, and the same solid as the dexels.

use swarf_geom::math::Vec3;
use swarf_stock::TriDexel;
use swarf_sweep::ToolShape;
use swarf_tool::Cutter;

#[test]
fn slotted_block_meshes_closed_with_the_dexel_volume_and_crisp_walls() {
    let h = 0.25;
    let mut stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(40.0, 20.0, 10.0), h).unwrap();
    let tool = ToolShape::new(&Cutter::flat(6.0).unwrap());
    // A through slot along X, 4 mm deep, and a ball pocket.
    stock.cut_linear(
        &tool,
        Vec3::new(-5.0, 10.0, 6.0),
        Vec3::new(45.0, 10.0, 6.0),
        Vec3::Z,
    );
    let ball = ToolShape::new(&Cutter::ball(8.0).unwrap());
    stock.cut_linear(
        &ball,
        Vec3::new(20.0, 4.0, 7.0),
        Vec3::new(20.0, 4.0, 7.0),
        Vec3::Z,
    );
    let (mesh, stats) = stock.to_mesh(&Default::default());
    assert!(mesh.is_closed(), "{:?}", mesh.edge_report());
    let v_mesh = mesh.volume();
    let v_dexel = stock.volume();
    assert!(
        (v_mesh - v_dexel).abs() / v_dexel < 2e-3,
        "{v_mesh} vs {v_dexel}"
    );
    assert_eq!(stats.fallback_crossings, 0, "{stats:?}");
    // The slot walls are planes y = 7 and y = 13: every vertex near them lies on them.
    let on_wall = mesh.vertices.iter().filter(|p| {
        p.z > 6.5
            && p.z < 9.5
            && p.x > 30.0
            && ((p.y - 7.0).abs() < 0.2 || (p.y - 13.0).abs() < 0.2)
    });
    let mut n = 0;
    for p in on_wall {
        n += 1;
        let d = (p.y - 7.0).abs().min((p.y - 13.0).abs());
        assert!(d < 1e-9, "wall vertex {p} is {d} mm off its wall");
    }
    assert!(n > 50, "{n} wall vertices");
}

/// The machined part as its STL stores it (`f32`, welded by position when read back) is a
/// 2-manifold without degenerate triangles, on many random programs of lines, arcs, full
/// circles, helices and plunges with several cutters.
#[test]
fn machined_parts_as_written_are_2_manifolds_on_random_programs() {
    use swarf_path::load::{read_program_str, ReadOptions};
    use swarf_path::Machine;
    use swarf_stock::{simulate, SimOptions};
    use swarf_tool::{ToolSet, ToolSource};
    let cutters = [
        Cutter::flat(6.0).unwrap(),
        Cutter::ball(6.0).unwrap(),
        Cutter::bull(8.0, 1.5).unwrap(),
        Cutter::chamfer(8.0, 90.0).unwrap(),
    ];
    let mut seed = 0x5EED_0015_u64;
    let mut next = move || {
        seed ^= seed >> 12;
        seed ^= seed << 25;
        seed ^= seed >> 27;
        (seed.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    };
    for case in 0..24 {
        let q = |v: f64| (v * 4.0).round() / 4.0;
        let mut text = String::from("G21 G90\nG0 X10 Y10 Z5\nG1 Z-1 F200\n");
        let (mut x, mut y) = (10.0, 10.0);
        for _ in 0..1 + (next() * 4.0) as usize {
            let (nx, ny, nz) = (
                q(2.0 + 16.0 * next()),
                q(2.0 + 16.0 * next()),
                q(-3.0 * next()),
            );
            match (next() * 4.0) as u32 {
                0 => {
                    text.push_str(&format!("G1 X{nx} Y{ny} Z{nz}\n"));
                    (x, y) = (nx, ny);
                }
                1 => text.push_str(&format!(
                    "G2 X{x} Y{y} I{} J0 Z{nz}\n",
                    q(1.0 + 4.0 * next())
                )),
                2 => {
                    let r = (nx - x).hypot(ny - y) / 2.0 + 0.5 + 4.0 * next();
                    text.push_str(&format!("G3 X{nx} Y{ny} R{r:.3}\n"));
                    (x, y) = (nx, ny);
                }
                _ => text.push_str(&format!("G1 Z{nz}\n")),
            }
        }
        text.push_str("M30\n");
        let program = read_program_str(
            &text,
            "r.ngc",
            Machine::three_axis(),
            &ReadOptions::default(),
        )
        .unwrap();
        let cutter = &cutters[case % cutters.len()];
        let tools = ToolSet::default().with(0, cutter.clone(), ToolSource::Spec);
        let h = [0.25, 0.3, 0.2][case % 3];
        let mut stock =
            TriDexel::from_box(Vec3::new(0.0, 0.0, -6.0), Vec3::new(20.0, 20.0, 0.0), h).unwrap();
        simulate(&program, &tools, &mut stock, &SimOptions::default()).unwrap();
        let (mesh, _) = stock.to_mesh(&Default::default());
        let what = format!("case {case}, h = {h}, {}:\n{text}", cutter.spec());
        assert_manifold_as_written(&mesh, &what);
    }
}

/// Panics unless `m` is a 2-manifold as an STL file stores it (`f32` positions welded when read
/// back; `TriMesh::manifold_defect`).
fn assert_manifold_as_written(m: &swarf_io::TriMesh, what: &str) {
    let mut bytes = Vec::new();
    swarf_io::write_stl_to(&mut bytes, m).unwrap();
    let w = swarf_io::stl::parse_stl(&bytes, std::path::Path::new("stock.stl")).unwrap();
    assert_eq!(
        w.triangles.len(),
        m.triangles.len(),
        "{what}: triangles lost"
    );
    if let Some(defect) = w.manifold_defect() {
        panic!("{what}: {defect}");
    }
}

#[test]
fn stock_meshes_of_real_stl_parts_are_2_manifolds() {
    // Issue 16 item 5: STL stocks meshed with edges in four or six triangles. The shared parts
    // (a mould core and a SolidWorks part) at several resolutions, as built and after a cut.
    let Some([core, part]) =
        swarf_testdata::paths(["stl/ocl_ktoolcor.stl", "stl/swcam_Paralelipipedo.stl"])
    else {
        return;
    };
    let cases = [(core, [0.05, 0.037], 1.0), (part, [5.0, 3.3], 40.0)];
    for (file, resolutions, d) in cases {
        let bytes = std::fs::read(&file).unwrap();
        for h in resolutions {
            let mut stock = TriDexel::from_stl_bytes(&bytes, h, Default::default()).unwrap();
            let what = format!("{} at h = {h}", file.display());
            assert_manifold_as_written(&stock.to_mesh(&Default::default()).0, &what);
            // A ball groove across the top, through the part's skin.
            let g = *stock.grid();
            let (lo, hi) = (g.min, g.max);
            let y = 0.5 * (lo.y + hi.y);
            let tool = ToolShape::new(&Cutter::ball(d).unwrap());
            stock.cut_linear(
                &tool,
                Vec3::new(lo.x - d, y, hi.z - 0.3 * d),
                Vec3::new(hi.x + d, y + 0.1 * (hi.y - lo.y), hi.z - 0.3 * d),
                Vec3::Z,
            );
            let what = format!("{what}, grooved");
            assert_manifold_as_written(&stock.to_mesh(&Default::default()).0, &what);
        }
    }
}
