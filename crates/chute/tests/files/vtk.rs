//! VTU frames and the PVD collection: well-formed XML with consistent counts and offsets.

use std::collections::HashMap;
use std::fs;

use chute::output::vtk::{VtkSeries, VTK_LINE, VTK_TRIANGLE};

/// A parsed XML element: name, attributes, text content and children.
#[derive(Debug)]
struct Node {
    name: String,
    attrs: HashMap<String, String>,
    text: String,
    children: Vec<Node>,
}

impl Node {
    fn child(&self, name: &str) -> &Node {
        self.children
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("no <{name}>"))
    }
    fn array(&self, name: &str) -> &Node {
        self.children
            .iter()
            .find(|c| {
                c.name == "DataArray" && c.attrs.get("Name").map(String::as_str) == Some(name)
            })
            .unwrap_or_else(|| panic!("no DataArray {name}"))
    }
    fn numbers(&self) -> Vec<f64> {
        self.text
            .split_whitespace()
            .map(|w| w.parse().unwrap())
            .collect()
    }
}

/// Minimal XML parser for the subset we write (declaration, elements, attributes in double
/// quotes, text). Panics on anything malformed: mismatched or unclosed tags, stray '<', junk.
fn parse_xml(src: &str) -> Node {
    let src = src.trim_start();
    let mut rest = src.strip_prefix("<?xml").expect("XML declaration");
    rest = &rest[rest.find("?>").expect("declaration end") + 2..];
    let mut stack: Vec<Node> = vec![Node {
        name: "#doc".into(),
        attrs: HashMap::new(),
        text: String::new(),
        children: vec![],
    }];
    while let Some(lt) = rest.find('<') {
        stack.last_mut().unwrap().text.push_str(&rest[..lt]);
        let gt = lt + rest[lt..].find('>').expect("unterminated tag");
        let tag = &rest[lt + 1..gt];
        rest = &rest[gt + 1..];
        assert!(!tag.contains('<'), "stray '<' in {tag}");
        if let Some(name) = tag.strip_prefix('/') {
            let node = stack.pop().unwrap();
            assert_eq!(node.name, name.trim(), "mismatched closing tag");
            stack.last_mut().unwrap().children.push(node);
            continue;
        }
        let self_closing = tag.ends_with('/');
        let tag = tag.trim_end_matches('/');
        let (name, mut attr_src) = tag.split_once(' ').unwrap_or((tag, ""));
        let mut attrs = HashMap::new();
        while let Some(eq) = attr_src.find("=\"") {
            let key = attr_src[..eq].trim().to_string();
            let close = eq
                + 2
                + attr_src[eq + 2..]
                    .find('"')
                    .expect("unterminated attribute");
            assert!(
                !key.is_empty() && !key.contains(' '),
                "bad attribute name {key:?}"
            );
            assert!(attrs
                .insert(key, attr_src[eq + 2..close].to_string())
                .is_none());
            attr_src = &attr_src[close + 1..];
        }
        assert!(attr_src.trim().is_empty(), "junk in tag: {attr_src:?}");
        let node = Node {
            name: name.into(),
            attrs,
            text: String::new(),
            children: vec![],
        };
        if self_closing {
            stack.last_mut().unwrap().children.push(node);
        } else {
            stack.push(node);
        }
    }
    assert!(rest.trim().is_empty(), "trailing text");
    assert_eq!(stack.len(), 1, "unclosed elements");
    let mut doc = stack.pop().unwrap();
    assert_eq!(doc.children.len(), 1, "exactly one root element");
    doc.children.pop().unwrap()
}

/// Positions, velocities, triangles, segments, triangle drag.
type Mesh = (
    Vec<[f64; 3]>,
    Vec<[f64; 3]>,
    Vec<[usize; 3]>,
    Vec<[usize; 2]>,
    Vec<[f64; 3]>,
);

/// Two triangles sharing an edge plus two suspension-line segments to a payload node.
fn mesh(t: f64) -> Mesh {
    let x = vec![
        [0.0, 0.0, 10.0 - t],
        [1.0, 0.0, 10.0 - t],
        [1.0, 1.0, 10.2 - t],
        [0.0, 1.0, 10.0 - t],
        [0.5, 0.5, 8.0 - t],
    ];
    let v = vec![[0.1, 0.0, -1.0 - t]; 5];
    let tri = vec![[0, 1, 2], [0, 2, 3]];
    let seg = vec![[0, 4], [2, 4]];
    let drag = vec![[0.0, 0.5, 3.25], [0.1, -0.2, 1e-17]];
    (x, v, tri, seg, drag)
}

#[test]
fn vtu_and_pvd_are_well_formed_and_consistent() {
    let dir = tempfile::tempdir().unwrap();
    let mut vtk = VtkSeries::new(dir.path()).unwrap();
    let times = [0.0, 0.125, 0.25];
    for (k, &t) in times.iter().enumerate() {
        let (x, v, tri, seg, drag) = mesh(t);
        let p = vtk.write_frame(t, &x, &v, &tri, &seg, &drag).unwrap();
        assert!(p.ends_with(format!("frames/frame_{k:06}.vtu")));
        // After each frame the PVD lists exactly the frames written so far.
        let pvd = parse_xml(&fs::read_to_string(dir.path().join("canopy.pvd")).unwrap());
        assert_eq!(pvd.attrs["type"], "Collection");
        let sets = &pvd.child("Collection").children;
        assert_eq!(sets.len(), k + 1);
        for (j, ds) in sets.iter().enumerate() {
            assert_eq!(ds.attrs["timestep"].parse::<f64>().unwrap(), times[j]);
            assert!(dir.path().join(&ds.attrs["file"]).is_file());
        }
    }
    let (x, v, tri, seg, drag) = mesh(0.25);
    let vtu = parse_xml(&fs::read_to_string(dir.path().join("frames/frame_000002.vtu")).unwrap());
    assert_eq!(vtu.attrs["type"], "UnstructuredGrid");
    let grid = vtu.child("UnstructuredGrid");
    assert_eq!(
        grid.child("FieldData").array("TimeValue").numbers(),
        vec![0.25]
    );
    let piece = grid.child("Piece");
    let n_cells = tri.len() + seg.len();
    assert_eq!(piece.attrs["NumberOfPoints"], x.len().to_string());
    assert_eq!(piece.attrs["NumberOfCells"], n_cells.to_string());
    let pts = piece.child("Points").array("Points");
    assert_eq!(pts.attrs["NumberOfComponents"], "3");
    assert_eq!(pts.numbers(), x.concat());
    assert_eq!(
        piece.child("PointData").array("velocity").numbers(),
        v.concat()
    );
    let cell_drag = piece.child("CellData").array("drag").numbers();
    assert_eq!(cell_drag.len(), 3 * n_cells);
    assert_eq!(cell_drag[..6], drag.concat()[..]);
    assert!(
        cell_drag[6..].iter().all(|&d| d == 0.0),
        "segments carry zero drag"
    );
    let cells = piece.child("Cells");
    let conn = cells.array("connectivity").numbers();
    let offsets = cells.array("offsets").numbers();
    let types = cells.array("types").numbers();
    assert_eq!(conn, vec![0., 1., 2., 0., 2., 3., 0., 4., 2., 4.]);
    assert_eq!(offsets, vec![3., 6., 8., 10.]);
    assert_eq!(*offsets.last().unwrap() as usize, conn.len());
    let (t, l) = (f64::from(VTK_TRIANGLE), f64::from(VTK_LINE));
    assert_eq!(types, vec![t, t, l, l]);
    // No temporary files left behind anywhere.
    let frames: Vec<_> = fs::read_dir(dir.path().join("frames")).unwrap().collect();
    assert_eq!(frames.len(), 3);
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 2); // frames/ and canopy.pvd
}

#[test]
fn inconsistent_input_is_rejected_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let mut vtk = VtkSeries::new(dir.path()).unwrap();
    let (x, v, tri, seg, drag) = mesh(0.0);
    assert!(vtk
        .write_frame(0.0, &x, &v[..4], &tri, &seg, &drag)
        .is_err());
    assert!(vtk
        .write_frame(0.0, &x, &v, &tri, &seg, &drag[..1])
        .is_err());
    assert!(vtk
        .write_frame(0.0, &x, &v, &tri, &[[0, 5]], &drag)
        .is_err());
    assert_eq!(vtk.frames(), 0);
    assert_eq!(fs::read_dir(dir.path().join("frames")).unwrap().count(), 0);
    assert!(!dir.path().join("canopy.pvd").exists());
}

#[test]
fn xml_checker_rejects_malformed_documents() {
    // The checker must be able to fail, or the test above proves nothing.
    for bad in [
        "<?xml version=\"1.0\"?><a><b></a></b>",
        "<?xml version=\"1.0\"?><a><b></b>",
        "<?xml version=\"1.0\"?><a x=\"1\" x=\"2\"/>",
        "<?xml version=\"1.0\"?><a x=1/>",
    ] {
        assert!(
            std::panic::catch_unwind(|| parse_xml(bad)).is_err(),
            "{bad}"
        );
    }
}

/// The area of triangle `t` with corners `x`.
fn area(x: &[f64], t: [usize; 3]) -> f64 {
    let p = |i: usize| [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
    let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
    let (u, v) = (
        [0, 1, 2].map(|k| b[k] - a[k]),
        [0, 1, 2].map(|k| c[k] - a[k]),
    );
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}

/// A no-compression fabric canopy's frames carry `wrinkle_strain` and `membrane_state` per
/// cell, consistent with the kinematics: a triangle whose area shrank by more than the
/// regularisation allows cannot be taut (a taut triangle has both principal strains ≳ −ε_r,
/// so its area ratio is ≥ 1 − 2ε_r to first order); a wrinkled one has a wrinkle strain
/// above ε_r; and the inflating canopy wrinkles somewhere (its skirt is drawn in by the lines).
#[test]
fn fabric_frames_show_where_the_membrane_wrinkles() {
    let sets = [
        "canopy.edge_length_m=0.25",
        "time.duration_s=0.3",
        "output.frame_interval_s=0.1",
        "output.snapshots_s=[]",
    ]
    .map(String::from);
    let path = crate::common::repo().join("scenarios/round-fabric.toml");
    let s = chute::scenario::Scenario::load(&path, &sets).unwrap();
    // (1e-5: the default of `material.wrinkle_strain`, docs/scenarios.md.)
    let eps_r = s.material.wrinkle_strain.unwrap_or(1e-5);
    let dir = tempfile::tempdir().unwrap();
    let (b, _) = crate::common::run_complete(&s, dir.path());
    let q0 = chute::build::build(&s).unwrap().state.q;
    let src = fs::read_to_string(dir.path().join("frames/frame_000003.vtu")).unwrap();
    let piece = parse_xml(&src);
    let piece = piece.child("UnstructuredGrid").child("Piece");
    let cells = piece.child("CellData");
    let strain = cells.array("wrinkle_strain").numbers();
    let state = cells.array("membrane_state").numbers();
    let n_tri = b.triangles.len();
    assert_eq!(strain.len(), n_tri + b.segments.len());
    assert_eq!(state.len(), strain.len());
    assert!(strain[n_tri..]
        .iter()
        .chain(&state[n_tri..])
        .all(|&x| x == 0.0));
    let x: Vec<f64> = piece.child("Points").array("Points").numbers();
    assert_eq!(x.len(), 3 * b.model.layout.n_nodes);
    let (mut wrinkled, mut shrunk) = (0, 0);
    for (i, &t) in b.triangles.iter().enumerate() {
        assert!([0.0, 1.0, 2.0].contains(&state[i]), "{}", state[i]);
        let shrink = 1.0 - area(&x, t) / area(&q0, t);
        if shrink > 10.0 * eps_r {
            shrunk += 1;
            assert!(
                state[i] >= 1.0,
                "triangle {i} shrank by {shrink} but is taut"
            );
        }
        if state[i] >= 1.0 {
            wrinkled += 1;
            assert!(strain[i] > eps_r, "triangle {i}: {} ≤ ε_r", strain[i]);
        } else {
            assert!(
                strain[i] <= eps_r,
                "triangle {i}: {} > ε_r while taut",
                strain[i]
            );
        }
    }
    assert!(wrinkled > 0, "no wrinkled triangle of {n_tri}");
    assert!(
        shrunk > 0,
        "no triangle shrank: the kinematic check is empty"
    );
    // The final state is also drawn by membrane state.
    let png = dir.path().join(chute::output::plots::WRINKLES_PNG);
    assert!(png.is_file(), "no {}", png.display());
    // A membrane that carries compression has no such fields and no such picture.
    let springs = crate::common::shell(0.02);
    let dir = tempfile::tempdir().unwrap();
    crate::common::run_complete(&springs, dir.path());
    let src = fs::read_to_string(dir.path().join("frames/frame_000000.vtu")).unwrap();
    assert!(!src.contains("wrinkle_strain") && !src.contains("membrane_state"));
    assert!(!dir.path().join(chute::output::plots::WRINKLES_PNG).exists());
}
