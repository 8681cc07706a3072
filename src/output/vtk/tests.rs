use super::*;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penetrate-vtk-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Values whose bits a text round trip could lose: signed zero, a subnormal, the extremes,
/// infinities and a NaN with a payload.
fn awkward() -> Vec<f32> {
    vec![
        -0.0,
        f32::from_bits(1),
        f32::MAX,
        f32::MIN_POSITIVE,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::from_bits(0x7fc0_1234),
        1.0 / 3.0,
    ]
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Particles and a mesh come back bit for bit, fields by name and in order.
#[test]
fn a_frame_reads_back_bit_for_bit() {
    let dir = scratch("round-trip");
    let values = awkward();
    let n = values.len();
    let particles = Vtu {
        r: values.clone(),
        z: values.iter().rev().copied().collect(),
        triangles: None,
        point_data: vec![
            ("pressure".into(), values.clone()),
            ("a \"quoted\" & <odd> name".into(), vec![2.5; n]),
        ],
        cell_data: Vec::new(),
    };
    let mesh = Vtu {
        r: vec![0.0, 1.0, 0.0, 1.0],
        z: vec![0.0, 0.0, 1.0, 1.5],
        triangles: Some(vec![[0, 1, 2], [1, 3, 2]]),
        point_data: vec![("v_r".into(), vec![1.0, 2.0, 3.0, 4.0])],
        cell_data: vec![
            ("damage".into(), vec![0.25, f32::NAN]),
            ("failed".into(), vec![0.0, 1.0]),
        ],
    };
    let empty = Vtu::default();
    for (name, grid) in [
        ("particles", &particles),
        ("mesh", &mesh),
        ("empty", &empty),
    ] {
        let path = dir.join(format!("{name}.vtu"));
        write_vtu(&path, grid).unwrap();
        let back = read_vtu(&path).unwrap();
        assert_eq!(bits(&back.r), bits(&grid.r), "{name}");
        assert_eq!(bits(&back.z), bits(&grid.z), "{name}");
        assert_eq!(back.triangles, grid.triangles, "{name}");
        for (read, written) in [
            (&back.point_data, &grid.point_data),
            (&back.cell_data, &grid.cell_data),
        ] {
            let names =
                |f: &[(String, Vec<f32>)]| f.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
            assert_eq!(names(read), names(written), "{name}");
            for ((_, a), (_, b)) in read.iter().zip(written) {
                assert_eq!(bits(a), bits(b), "{name}");
            }
        }
    }
    assert_eq!(mesh.cells(), 2);
    assert_eq!(
        read_vtu(&dir.join("mesh.vtu"))
            .unwrap()
            .cell_field("failed"),
        Some(&[0.0, 1.0][..])
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A collection lists its frames in order, and a broken one is named.
#[test]
fn a_collection_reads_back() {
    let dir = scratch("pvd");
    let path = dir.join("frames.pvd");
    let mut pvd = Collection::new(path.clone());
    pvd.add(0.0, 0, "target_00000.vtu").unwrap();
    pvd.add(1.5e-6, 1, "projectile_00001.vtu").unwrap();
    let listed = read_pvd(&path).unwrap();
    let expected = [
        (0.0, 0, "target_00000.vtu"),
        (1.5e-6, 1, "projectile_00001.vtu"),
    ];
    let expected: Vec<DataSet> = expected
        .iter()
        .map(|&(time, part, file)| DataSet {
            time,
            part,
            file: file.into(),
        })
        .collect();
    assert_eq!(listed, expected);
    for (text, why) in [
        (
            "<VTKFile type=\"UnstructuredGrid\">",
            "not a VTK collection",
        ),
        (
            "<VTKFile type=\"Collection\"><DataSet timestep=\"x\" file=\"a\"/>",
            "is not a number",
        ),
        (
            "<VTKFile type=\"Collection\"><DataSet timestep=\"0\"/>",
            "has no file",
        ),
    ] {
        std::fs::write(&path, text).unwrap();
        let e = read_pvd(&path).unwrap_err();
        assert!(e.contains("frames.pvd") && e.contains(why), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The ASCII frames of earlier runs are read too.
#[test]
fn an_ascii_frame_reads() {
    let text = r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
<UnstructuredGrid>
<Piece NumberOfPoints="3" NumberOfCells="1">
<Points>
<DataArray type="Float32" NumberOfComponents="3" format="ascii">
0 0 0
1 0 0.5
0 0 1e-3
</DataArray>
</Points>
<Cells>
<DataArray type="Int32" Name="connectivity" format="ascii">
0 1 2
</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">
3 </DataArray>
<DataArray type="UInt8" Name="types" format="ascii">
5 </DataArray>
</Cells>
<PointData>
<DataArray type="Float32" Name="v_r" format="ascii">
1 2 3 </DataArray>
</PointData>
<CellData>
<DataArray type="Float32" Name="damage" format="ascii">
0.5 </DataArray>
</CellData>
</Piece>
</UnstructuredGrid>
</VTKFile>
"#;
    let grid = parse(text.as_bytes()).unwrap();
    assert_eq!(grid.r, vec![0.0, 1.0, 0.0]);
    assert_eq!(grid.z, vec![0.0, 0.5, 1e-3]);
    assert_eq!(grid.triangles, Some(vec![[0, 1, 2]]));
    assert_eq!(grid.point_field("v_r"), Some(&[1.0, 2.0, 3.0][..]));
    assert_eq!(grid.cell_field("damage"), Some(&[0.5][..]));
}

/// A file that is not a frame, or a frame cut short or altered, is an error saying what is
/// wrong, never a panic; so is one that is not a regular file.
#[test]
fn a_malformed_frame_is_an_error() {
    let dir = scratch("malformed");
    let path = dir.join("mesh.vtu");
    let mesh = Vtu {
        r: vec![0.0, 1.0, 0.0],
        z: vec![0.0, 0.0, 1.0],
        triangles: Some(vec![[0, 1, 2]]),
        point_data: Vec::new(),
        cell_data: vec![("damage".into(), vec![0.5])],
    };
    write_vtu(&path, &mesh).unwrap();
    let good = std::fs::read(&path).unwrap();
    // The header edited, the appended data kept.
    let split = good
        .windows(13)
        .position(|w| w == b"<AppendedData")
        .unwrap();
    let header = std::str::from_utf8(&good[..split]).unwrap();
    let edit = |from: &str, to: &str| -> Vec<u8> {
        let mut bytes = header.replace(from, to).into_bytes();
        bytes.extend_from_slice(&good[split..]);
        bytes
    };
    let data = good.windows(3).position(|w| w == b">\n_").unwrap() + 3;
    let mut cases: Vec<(Vec<u8>, &str)> = vec![
        (Vec::new(), "does not start with <VTKFile>"),
        (b"\xff\xfe garbage".to_vec(), "not UTF-8"),
        (
            b"<VTKFile type=\"PolyData\">".to_vec(),
            "not an UnstructuredGrid",
        ),
        (good[..data + 20].to_vec(), "run past the end of the file"),
        (good[..data - 1].to_vec(), "does not start with `_`"),
        (good[..data - 3].to_vec(), "<AppendedData> does not end"),
        (
            edit("byte_order=\"LittleEndian\"", "byte_order=\"BigEndian\""),
            "BigEndian",
        ),
        (edit("UInt64", "Int16"), "header_type Int16"),
        (
            edit("NumberOfCells=\"1\"", "NumberOfCells=\"2\""),
            "holds 1 values, not 2",
        ),
        (
            edit(
                "NumberOfPoints=\"3\"",
                "NumberOfPoints=\"99999999999999999999\"",
            ),
            "is not a count",
        ),
        (
            edit(
                "NumberOfPoints=\"3\"",
                "NumberOfPoints=\"6148914691236517206\"",
            ),
            "too many values",
        ),
        (
            edit("Name=\"offsets\"", "Name=\"offset\""),
            "no offsets array",
        ),
        (
            edit(
                "type=\"Float32\" Name=\"damage\"",
                "type=\"Float64\" Name=\"damage\"",
            ),
            "Float64 is not read",
        ),
        (
            edit(
                "format=\"appended\" offset=\"0\"",
                "format=\"binary\" offset=\"0\"",
            ),
            "format \"binary\"",
        ),
        (edit("<Piece", "<Piece\""), "a tag does not end"),
        (
            edit(" NumberOfCells=\"1\"", " NumberOfCells"),
            "not key=\"value\"",
        ),
    ];
    let mut encoded = good.clone();
    let at = split + "<AppendedData encoding=\"".len();
    encoded[at..at + 3].copy_from_slice(b"b64");
    cases.push((encoded, "encoded as b64, not raw"));
    // A corner that names no point, and a cell type other than a vertex or a triangle.
    let mut outside = good.clone();
    let connectivity = data + 3 * 12 + 8 + 8;
    outside[connectivity..connectivity + 4].copy_from_slice(&7i32.to_le_bytes());
    cases.push((outside, "cell 0 names point 7 of 3"));
    let mut quad = good.clone();
    let types = data + 8 + 36 + 8 + 12 + 8 + 4 + 8;
    quad[types] = 9;
    cases.push((quad, "VTK type 9"));
    let mut huge = good.clone();
    huge[data..data + 8].copy_from_slice(&u64::MAX.to_le_bytes());
    cases.push((huge, "run past the end"));
    // Cut anywhere or with any byte flipped, it reads or is refused.
    for k in 0..good.len() {
        let _ = parse(&good[..k]);
        let mut flipped = good.clone();
        flipped[k] ^= 0xff;
        let _ = parse(&flipped);
    }
    for (bytes, why) in cases {
        std::fs::write(&path, &bytes).unwrap();
        let e = read_vtu(&path).unwrap_err();
        assert!(
            e.starts_with(&path.display().to_string()) && e.contains(why),
            "{why}: {e}"
        );
    }
    std::fs::remove_file(&path).unwrap();
    assert!(read_vtu(&path).unwrap_err().contains("mesh.vtu"));
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/dev/zero", &path).unwrap();
        assert!(read_vtu(&path).unwrap_err().contains("not a regular file"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
