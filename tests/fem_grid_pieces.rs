//! FEM's grid file on several ranks (issue 27): each rank writes its owned elements and
//! their nodes (the node layer of a cut in both pieces beside it) as
//! `fem_grid_<frame>_r<rank>.vtu` from its own memory, rank 0 lists the pieces in rank
//! order in `fem_grid_<frame>.pvtu`, and `fem_grid.pvd` lists the `.pvtu` files; no
//! `fem_grid_<frame>.vtu` is written whole. Run on in-process ranks (`ThreadComm`) through
//! the file writer the CLI uses, on slabs (2 and 3 ranks) and boxes (2 × 2 on 4), the
//! pieces' cells together are the one-rank file's bit for bit: every cell in exactly one
//! piece, keyed by its corners' deformed positions, with its stress and velocity and each
//! corner's nodal velocity. The files are read back from the bytes (zlib-compressed raw
//! appended arrays, `impact_io::vtu`), not from the writer's buffers. No mesh is gathered:
//! at each output a rank other than 0 receives less than one value per element (the
//! measuring line's samples and a few counts; rank 0 also receives the figures' map plane),
//! counted by a [`Comm`] that wraps the thread ranks'.
use impact::output::pieces::Pieces;
use impact::output::FileWriter;
use impact::run::Observer;
use impact_core::comm::{Comm, RankGrid, ThreadComm};
use impact_core::method::{MethodKind, Model};
use impact_core::reference::TimeMetrics;
use impact_core::{Method, Problem, Scene};
use impact_fem::slab::SlabFem;
use impact_fem::Fem;
use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// The frames written: the initial state and two output times.
const FRAMES: [&str; 3] = ["initial", "t0", "t1"];

/// Steps between the outputs.
const STEPS: usize = 25;

/// One array of a `.vtu`: components per entry and the values' bits.
type Array = (usize, Vec<u64>);

/// A `.vtu` read back: the points (bits), the cells' vertices, the point and cell arrays.
struct Vtu {
    points: Vec<[u64; 3]>,
    cells: Vec<Vec<usize>>,
    point_data: BTreeMap<String, Array>,
    cell_data: BTreeMap<String, Array>,
}

/// The raw bytes of the binary payload at `at` of the appended section: the UInt64 header
/// `[blocks, block size, last block size, compressed sizes...]`, then zlib blocks.
fn decode(appended: &[u8], at: usize) -> Vec<u8> {
    let word = |k: usize| {
        let b = &appended[at + 8 * k..at + 8 * k + 8];
        u64::from_le_bytes(b.try_into().unwrap()) as usize
    };
    let blocks = word(0);
    let mut from = at + 8 * (3 + blocks);
    let mut raw = Vec::new();
    for k in 0..blocks {
        let size = word(3 + k);
        let mut decoder = flate2::read::ZlibDecoder::new(&appended[from..from + size]);
        decoder.read_to_end(&mut raw).unwrap();
        from += size;
    }
    raw
}

/// Read a binary `.vtu` of `impact_io::vtu::write_vtu`.
fn read_vtu(path: &Path) -> Vtu {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let marker: &[u8] = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .unwrap_or_else(|| panic!("{}: no appended data", path.display()));
    let appended = &bytes[at + marker.len()..];
    let appended = &appended[appended.iter().position(|&b| b == b'_').unwrap() + 1..];
    // (the XML before the appended section, closed)
    let head = format!("{}</VTKFile>", std::str::from_utf8(&bytes[..at]).unwrap());
    let doc = roxmltree::Document::parse(&head).unwrap();
    let mut sections: BTreeMap<(String, String), Array> = BTreeMap::new();
    for node in doc.descendants().filter(|n| n.has_tag_name("DataArray")) {
        let Some(offset) = node.attribute("offset") else {
            continue; // (the inline TimeValue)
        };
        let raw = decode(appended, offset.parse().unwrap());
        let values: Vec<u64> = match node.attribute("type").unwrap() {
            "Float64" | "Int64" => raw
                .chunks_exact(8)
                .map(|c| u64::from_le_bytes(c.try_into().unwrap()))
                .collect(),
            _ => raw.iter().map(|&b| u64::from(b)).collect(),
        };
        let components = node
            .attribute("NumberOfComponents")
            .unwrap()
            .parse()
            .unwrap();
        let section = node.parent().unwrap().tag_name().name().to_string();
        let name = node.attribute("Name").unwrap().to_string();
        sections.insert((section, name), (components, values));
    }
    let take = |section: &str, name: &str| sections[&(section.into(), name.into())].1.clone();
    let points = take("Points", "Points")
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    let connectivity = take("Cells", "connectivity");
    let mut cells = Vec::new();
    let mut from = 0;
    for end in take("Cells", "offsets") {
        cells.push(
            (from..end as usize)
                .map(|k| connectivity[k] as usize)
                .collect(),
        );
        from = end as usize;
    }
    let of = |section: &str| {
        (sections.iter())
            .filter(|((s, _), _)| s == section)
            .map(|((_, n), a)| (n.clone(), a.clone()))
            .collect()
    };
    Vtu {
        points,
        cells,
        point_data: of("PointData"),
        cell_data: of("CellData"),
    }
}

/// A cell as the files show it: its corners (deformed position and nodal velocity, bits,
/// sorted by position) and its cell arrays.
type Cell = (Vec<([u64; 3], Vec<u64>)>, BTreeMap<String, Vec<u64>>);

/// The cells of a grid `.vtu`, keyed by their corners' positions.
fn cells_of(path: &Path) -> BTreeMap<Vec<[u64; 3]>, Cell> {
    let vtu = read_vtu(path);
    let (k, nodal) = &vtu.point_data["nodal_velocity"];
    assert_eq!((*k, nodal.len()), (3, 3 * vtu.points.len()), "{path:?}");
    let mut out = BTreeMap::new();
    for (c, vertices) in vtu.cells.iter().enumerate() {
        let mut corners: Vec<([u64; 3], Vec<u64>)> = (vertices.iter())
            .map(|&v| (vtu.points[v], nodal[3 * v..3 * v + 3].to_vec()))
            .collect();
        corners.sort();
        let arrays = (vtu.cell_data.iter())
            .map(|(name, (k, values))| (name.clone(), values[k * c..k * (c + 1)].to_vec()))
            .collect();
        let key: Vec<[u64; 3]> = corners.iter().map(|c| c.0).collect();
        let previous = out.insert(key, (corners, arrays));
        assert!(previous.is_none(), "{path:?}: cell {c} twice");
    }
    out
}

/// A rank's [`Comm`] that counts the bytes it receives from the other ranks.
#[derive(Debug)]
struct Counting {
    inner: Arc<dyn Comm>,
    received: AtomicUsize,
}

impl Counting {
    fn add(&self, bytes: usize) {
        self.received.fetch_add(bytes, Ordering::Relaxed);
    }
}

impl Comm for Counting {
    fn rank(&self) -> usize {
        self.inner.rank()
    }
    fn size(&self) -> usize {
        self.inner.size()
    }
    fn all_gather_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>) {
        self.inner.all_gather_into(local, out, counts);
        self.add(8 * (out.len() - local.len()));
    }
    fn all_gather_bytes(&self, local: &[u8], out: &mut Vec<u8>, counts: &mut Vec<usize>) {
        self.inner.all_gather_bytes(local, out, counts);
        self.add(out.len() - local.len());
    }
    fn gather_to_root_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>) {
        self.inner.gather_to_root_into(local, out, counts);
        self.add(8 * out.len().saturating_sub(local.len()));
    }
    /// (the halo of a step: counted, though no output exchanges one)
    fn exchange(
        &self,
        sides: [Option<usize>; 2],
        to_low: &[f64],
        to_high: &[f64],
        from_low: &mut [f64],
        from_high: &mut [f64],
    ) {
        (self.inner).exchange(sides, to_low, to_high, from_low, from_high);
        let bytes = |n: Option<usize>, b: &[f64]| n.map_or(0, |_| 8 * b.len());
        self.add(bytes(sides[0], from_low) + bytes(sides[1], from_high));
    }
    fn barrier(&self) {
        self.inner.barrier();
    }
    fn abort(&self, code: i32) -> ! {
        self.inner.abort(code)
    }
}

/// Write `m`'s grid frames (the initial state, then an output every [`STEPS`] steps) with
/// the CLI's writer into `dir`, this rank's pieces into `pieces` on several ranks; the
/// most bytes `counted` says were received during one output call.
fn write_frames(
    problem: &Problem<2>,
    m: &mut dyn Method<2>,
    dir: &Path,
    pieces: Option<Pieces>,
    rank_grid: &RankGrid,
    counted: Option<&Counting>,
) -> usize {
    let received = || counted.map_or(0, |c| c.received.load(Ordering::Relaxed));
    let mut most = 0;
    std::fs::create_dir_all(dir).unwrap();
    let mut writer = FileWriter::<2>::new(dir, "fem", &problem.grid, None, None, problem.t_end);
    writer.pieces = pieces;
    writer.rank_grid = rank_grid.clone();
    writer.measure = problem.model.stress_measure();
    writer.line = impact_core::line::MeasureLine::of(problem);
    if problem.model == Model::LinearElastic {
        writer.plane_strain = Some(problem.material);
    }
    let before = received();
    writer.start(m).unwrap();
    most = most.max(received() - before);
    let dt = m.stable_dt();
    let mut t = 0.0;
    for index in 0..FRAMES.len() - 1 {
        for _ in 0..STEPS {
            m.step(t, dt);
            t += dt;
        }
        let metrics = TimeMetrics::without_reference(t, m.energy(), m.initial_energy());
        let before = received();
        writer.output(m, index, t, &metrics).unwrap();
        most = most.max(received() - before);
    }
    writer.finish().unwrap();
    most
}

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.toml"));
    Scene::parse_file(&path).unwrap()
}

/// `scene`'s FEM grid files on `ranks` ranks split as `rank_grid` against one rank's.
fn pieces_equal_the_serial_files(name: &str, ranks: usize, rank_grid: RankGrid) {
    let scene = scene(name);
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    let config = scene.method_config(MethodKind::Fem);
    let label = format!("{name} on {ranks} ranks, rank grid {:?}", rank_grid.0);
    // (removed when dropped, kept for inspection if an assertion fails)
    let root = crate::common::tmp(&format!("fem-pieces-{name}-{ranks}-{}", rank_grid.0.len()));
    let serial = root.join("serial");
    let mut fem = Fem::<2>::new(&problem, config).unwrap();
    write_frames(
        &problem,
        &mut fem,
        &serial,
        None,
        &RankGrid::automatic(),
        None,
    );
    let shared = root.join("split");
    let received = ThreadComm::on_ranks(ranks, |comm| {
        let rank = comm.rank();
        let counting = Arc::new(Counting {
            inner: comm,
            received: AtomicUsize::new(0),
        });
        let mut m = SlabFem::<2>::on_grid(&problem, config, counting.clone(), &rank_grid).unwrap();
        // rank 0 writes into the shared folder, the others into their own (as `impact run`)
        let own = match rank {
            0 => shared.clone(),
            r => root.join(format!("scratch{r}")),
        };
        let pieces = Pieces {
            dir: shared.clone(),
            rank,
            ranks,
        };
        write_frames(
            &problem,
            &mut m,
            &own,
            Some(pieces),
            &rank_grid,
            Some(&counting),
        )
    });
    // (before, every rank received every other rank's samples, 12 values per element, and
    // its nodes' velocity and displacement)
    let elements = problem.grid.cell_count();
    for (rank, &bytes) in received.iter().enumerate().skip(1) {
        assert!(
            bytes < 8 * elements,
            "{label}: rank {rank} received {bytes} B at an output, {elements} elements"
        );
    }
    let pvd = std::fs::read_to_string(shared.join("fem_grid.pvd")).unwrap();
    let mut moving = 0;
    for frame in FRAMES {
        let whole = cells_of(&serial.join(format!("fem_grid_{frame}.vtu")));
        assert!(
            !shared.join(format!("fem_grid_{frame}.vtu")).exists(),
            "{label}: {frame} written whole"
        );
        let pvtu = format!("fem_grid_{frame}.pvtu");
        assert!(pvd.contains(&format!("file=\"{pvtu}\"")), "{label}: {pvd}");
        let listing = std::fs::read_to_string(shared.join(&pvtu)).unwrap();
        assert!(
            listing.contains("Name=\"nodal_velocity\""),
            "{label}: {listing}"
        );
        let mut joined = BTreeMap::new();
        for r in 0..ranks {
            let piece = format!("fem_grid_{frame}_r{r}.vtu");
            assert!(listing.contains(&format!("Source=\"{piece}\"")), "{label}");
            let cells = cells_of(&shared.join(&piece));
            assert!(!cells.is_empty(), "{label}: {piece} has no cell");
            for (key, cell) in cells {
                assert!(
                    joined.insert(key, cell).is_none(),
                    "{label}: a cell of {piece} in another piece"
                );
            }
        }
        assert_eq!(joined.len(), whole.len(), "{label}, {frame}: cell count");
        for (key, cell) in &whole {
            let piece = joined.get(key);
            assert!(
                piece.is_some(),
                "{label}, {frame}: a serial cell in no piece"
            );
            assert!(piece == Some(cell), "{label}, {frame}: a cell differs");
            moving += usize::from(cell.0.iter().any(|(_, v)| v.iter().any(|&b| b != 0)));
        }
    }
    assert!(moving > 0, "{label}: the wave must move some node");
}

#[test]
fn fem_grid_pieces_on_slabs_are_the_serial_file() {
    pieces_equal_the_serial_files("plate", 2, RankGrid::automatic());
    pieces_equal_the_serial_files("plate", 3, RankGrid::automatic());
}

#[test]
fn fem_grid_pieces_on_boxes_are_the_serial_file() {
    pieces_equal_the_serial_files("plate", 4, RankGrid(vec![2, 2]));
}

#[test]
fn fem_grid_pieces_of_the_plastic_plate_are_the_serial_file() {
    pieces_equal_the_serial_files("ep-plate", 3, RankGrid::automatic());
}
