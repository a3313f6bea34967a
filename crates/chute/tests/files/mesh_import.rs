//! DisMech and OBJ importers: the bundled parachute meshes, rod chains, and malformed input
//! reported as `path:line: message` without panicking.
use crate::common::assert_contains;
use chute::mesh::{dismech, obj, CanopyMesh, MeshFileError};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data/meshes")
        .join(name)
}

#[test]
fn hexparachute_n6_counts_and_rod_chains() {
    let m = dismech::read(data("hexparachute_n6_python.txt")).unwrap();
    assert_eq!(m.n_nodes(), 188);
    assert_eq!(m.faces.len(), 216);
    assert_eq!(m.rod_edges.len(), 66);
    assert_eq!(m.shell_nodes().len(), 127);
    let rod = m.node_set("rod").unwrap().to_vec();
    assert_eq!(rod.len(), 61);
    let corners = m.node_set("corners").unwrap().to_vec();
    assert_eq!(corners.len(), 6);
    let chains = m.rod_chains();
    assert_eq!(chains.len(), 6);
    for c in &chains {
        assert_eq!(c.len(), 12, "11 edges: {c:?}");
        assert_eq!(c[0], 0, "every line starts at the payload node");
        assert!(
            corners.contains(c.last().unwrap()),
            "ends at a corner: {c:?}"
        );
        assert!(c[1..11].iter().all(|i| rod.contains(i)));
    }
    let tri = m.tri_mesh().unwrap();
    assert!(tri.vertex_faces[0].is_empty());
    assert_eq!(m.node_set("rim").unwrap().len(), 36);
}

#[test]
fn other_bundled_meshes_load() {
    let m = dismech::read(data("hexparachute_n12.txt")).unwrap();
    assert_eq!(
        (m.n_nodes(), m.faces.len(), m.rod_edges.len()),
        (674, 864, 210)
    );
    let m = dismech::read(data("hexparachute_n4_python.txt")).unwrap();
    assert_eq!((m.n_nodes(), m.faces.len(), m.rod_edges.len()), (22, 16, 9));
    // Three lines of 3 edges from the payload node to the rim.
    let lens: Vec<usize> = m.rod_chains().iter().map(Vec::len).collect();
    assert_eq!(lens, [4, 4, 4]);
}

#[test]
fn rod_chains_split_at_junctions_and_handle_loops() {
    let mut m = dismech::parse(
        "*Nodes\n0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 0\n3 1 0\n5 5 5\n6 5 5\n5 6 5\n\
         *Triangles\n1 2 3\n*Edges\n2 4\n4 5\n5 6\n5 7\n7 8\n8 9\n9 7\n",
        "t",
    )
    .unwrap();
    // 2 (shell) – 4 – 5 (junction); 5 – 6 (free end); 5 – 7 (junction) and a loop 7-8-9-7.
    assert_eq!(
        m.rod_chains(),
        vec![vec![1, 3, 4], vec![4, 5], vec![4, 6], vec![6, 7, 8, 6]]
    );
    m.rod_edges = vec![[6, 7], [7, 8], [8, 6]];
    assert_eq!(m.rod_chains(), vec![vec![6, 7, 8, 6]]);
}

#[test]
fn obj_faces_polygons_and_negative_indices() {
    let text = "# a quad and a triangle\no canopy\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\n\
                vt 0 0\nvn 0 0 1\ns off\nf 1/1/1 2/1/1 3/1/1 4/1/1\nv 2 0 0\nf -4 -1 -3\n";
    let m = obj::parse(text, "a.obj").unwrap();
    assert_eq!(m.n_nodes(), 5);
    assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3], [1, 4, 2]]);
    assert!(m.rod_edges.is_empty());
    let m = obj::parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", "b.obj").unwrap();
    assert_eq!(m.faces, vec![[0, 1, 2]]);
}

fn err(r: Result<CanopyMesh, MeshFileError>) -> String {
    r.expect_err("malformed input must be rejected").to_string()
}

/// Each `(text, want)` of `cases`: `parse` refuses `text` with a message starting with `want`.
fn assert_each_refused(
    cases: &[(String, &str)],
    parse: impl Fn(&str) -> Result<CanopyMesh, MeshFileError>,
) {
    for (text, want) in cases {
        let got = err(parse(text));
        assert!(
            got.starts_with(want),
            "input {text:?}:\n got  {got}\n want {want}…"
        );
    }
}

const HEAD: &str = "*Nodes\n0 0 0\n1 0 0\n0 1 0\n";

#[test]
fn malformed_dismech_files_name_file_and_line() {
    let cases: Vec<(String, &str)> = vec![
        (
            "*Nodes\n0, 0, 0\n1, 0, x\n".into(),
            "m.txt:3: bad number `x`",
        ),
        (
            "*Nodes\n0 0 0\n1 0 inf\n".into(),
            "m.txt:3: non-finite coordinate `inf`",
        ),
        (
            // A stray node, blamed on its line, not later on a drag or mass key.
            "*Nodes\n0 0 0\n1 0 1e30\n".into(),
            "m.txt:3: coordinate `1e30` m is beyond ±1000 m",
        ),
        (
            "*Nodes\n0 0 0\n1 0\n".into(),
            "m.txt:3: expected 3 coordinates, found 2 fields",
        ),
        ("0 0 0\n".into(), "m.txt:1: data before any section header"),
        (
            "*Nodes\n0 0 0\n*Shells\n".into(),
            "m.txt:3: unknown section `*Shells`",
        ),
        (
            format!("{HEAD}*Triangles\n1 2 4\n"),
            "m.txt:6: node index 4 out of range",
        ),
        (
            format!("{HEAD}*Triangles\n1 2 0\n"),
            "m.txt:6: node index 0",
        ),
        (
            format!("{HEAD}*Triangles\n1 2 -3\n"),
            "m.txt:6: bad node index `-3`",
        ),
        (
            format!("{HEAD}*Triangles\n1 2 99999999999999999999999\n"),
            "m.txt:6: bad node index",
        ),
        (
            format!("{HEAD}*Triangles\n1 2 2\n"),
            "m.txt:6: degenerate triangle 1 2 2: repeated node",
        ),
        (
            "*Nodes\n0 0 0\n1 0 0\n2 0 0\n*Triangles\n1 2 3\n".into(),
            "m.txt:6: degenerate triangle 1 2 3: zero area",
        ),
        (
            "*Nodes\n0 0 0\n1 0 0\n# c\n0 0 0\n".into(),
            "m.txt:5: node 3 duplicates node 1 (line 2)",
        ),
        (
            format!("{HEAD}1 1 0\n*Triangles\n1 2 3\n1 4 3\n"),
            "m.txt:8: triangle traverses edge",
        ),
        (
            format!("{HEAD}0 -1 0\n0 0 1\n*Triangles\n1 2 3\n2 1 4\n1 2 5\n"),
            "m.txt:10: non-manifold triangle: with it, edge 1–2 is shared by 3 triangles",
        ),
        (
            format!("{HEAD}1 1 0\n*Triangles\n1 2 3\n2 4 3\n3 1 2\n"),
            "m.txt:9: duplicate triangle 3 1 2: line 7 has the same three nodes",
        ),
        (
            format!("{HEAD}*Edges\n1 1\n"),
            "m.txt:6: rod edge joins node 1 to itself",
        ),
        (
            format!("{HEAD}*Edges\n1 9\n"),
            "m.txt:6: node index 9 out of range",
        ),
        ("*Nodes\n0 0 0\n".into(), "m.txt: no triangles found"),
        (String::new(), "m.txt: no triangles found"),
        (
            "*Triangles\n1, 2, 3\n".into(),
            "m.txt:2: node index 1 out of range",
        ),
    ];
    assert_each_refused(&cases, |text| dismech::parse(text, "m.txt"));
    // Headers are case-insensitive; commas, spaces, tabs and trailing comments all work.
    let ok = dismech::parse(
        "*NODES\n0,0,0\n1 , 0 0\n0\t1 0 # apex\n*triangles\n1,2,3\n",
        "m.txt",
    );
    assert_eq!(ok.unwrap().faces, vec![[0, 1, 2]]);
}

#[test]
fn malformed_obj_files_name_file_and_line() {
    let v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let cases: Vec<(String, &str)> = vec![
        (
            format!("{v}v 1 nan 0\n"),
            "o.obj:4: non-finite coordinate `nan`",
        ),
        (
            format!("{v}v 1 2\n"),
            "o.obj:4: expected 3 vertex coordinates, found 2",
        ),
        (format!("{v}f 1 2 x\n"), "o.obj:4: bad vertex index `x`"),
        (
            format!("{v}f 1 2\n"),
            "o.obj:4: a face needs at least 3 vertices",
        ),
        (format!("{v}f 1 2 0\n"), "o.obj:4: vertex index 0"),
        (
            format!("{v}f 1 2 -4\n"),
            "o.obj:4: relative vertex index -4 points before the first vertex",
        ),
        (
            format!("{v}f 1 2 7\n"),
            "o.obj:4: node index 7 out of range",
        ),
        (
            format!("{v}v 0 1 0\nf 1 2 3\n"),
            "o.obj:4: node 4 duplicates node 3 (line 3)",
        ),
        (
            format!("{v}f 1 2 2\n"),
            "o.obj:4: degenerate triangle 1 2 2",
        ),
        (
            format!("{v}v 2 0 0\nf 1 2 4\n"),
            "o.obj:5: degenerate triangle 1 2 4: zero area",
        ),
    ];
    assert_each_refused(&cases, |text| obj::parse(text, "o.obj"));
}

#[test]
fn missing_file_names_the_path_and_binary_garbage_does_not_panic() {
    let got = err(dismech::read("/nonexistent/dir/mesh.txt"));
    assert!(
        got.starts_with("/nonexistent/dir/mesh.txt: cannot read file"),
        "{got}"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("garbage.obj");
    let bytes: Vec<u8> = (0..4000u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    std::fs::write(&path, &bytes).unwrap();
    assert!(obj::read(&path).is_err());
    assert!(dismech::read(&path).is_err());
}

#[test]
fn unused_vertex_is_rejected_naming_file_line_and_node() {
    // The bundled DisMech parachute cut before its `*Edges`: the 61 line nodes are unused.
    let text = std::fs::read_to_string(data("hexparachute_n6_python.txt")).unwrap();
    let cut = &text[..text.find("*Edges").unwrap()];
    let got = err(dismech::parse(cut, "cut.txt"));
    let first = text.lines().position(|l| l.trim() == "*Nodes").unwrap() + 2;
    assert!(
        got.starts_with(&format!(
            "cut.txt:{first}: node 1 is on no triangle and no rod edge"
        )),
        "{got}"
    );
    assert_contains(&got, &["60 more unused nodes", "*Edges"]);
    // An OBJ with a stray vertex.
    let got = err(obj::parse(
        "v 0 0 0\nv 1 0 0\nv 5 5 5\nv 0 1 0\nf 1 2 4\n",
        "o.obj",
    ));
    assert!(
        got.starts_with(
            "o.obj:3: node 3 is on no triangle and no rod edge, so it would have no mass;"
        ),
        "{got}"
    );
}
