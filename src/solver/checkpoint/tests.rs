use super::*;
use crate::output::history::Row;

fn smoke() -> Scene {
    crate::scene::shipped_case("smoke.toml", &[])
}

/// The smoke model after `steps` CPU steps, and its checkpoint's bytes.
fn stepped(scene: &Scene, steps: usize) -> (Simulation, Vec<u8>) {
    let mut sim = Simulation::new(scene).unwrap();
    for _ in 0..steps {
        sim.step().unwrap();
    }
    let counters = Counters {
        frame: 3,
        frame_step: Some(7),
        history_step: steps as u64,
        next_history: 1.5e-6,
        next_frame: f64::MAX,
    };
    let mark = Mark {
        bytes: 1234,
        crc: 0xdead_beef,
        last: Some((
            Row {
                time: 1e-6,
                hits: 4,
                ..Row::default()
            },
            2.0,
            -3.0,
        )),
    };
    let frames = [(0.0, 0, "target_00000.vtu".to_string())];
    let table = scene.resolved_table();
    let m = sim.model().unwrap();
    let bytes = Parts::of(m, &table, &counters, &mark, Some(&frames)).encode();
    (sim, bytes)
}

/// What is decoded encodes to the same bytes (every field read back, in order, bit for
/// bit), and a model restored from it takes the same steps as the one it was written of.
#[test]
fn a_checkpoint_round_trips_and_steps_on_identically() {
    let sums = round_trip_and_step_on(&smoke());
    assert!(sums.is_empty());
}

/// The same with wall images, whose segments' last sums the next integration books.
#[test]
fn a_checkpoint_with_wall_images_steps_on_identically() {
    let scene = crate::scene::shipped_case("smoke.toml", &["contact.kernel=\"images\""]);
    let sums = round_trip_and_step_on(&scene);
    assert!(sums.iter().flatten().any(|&f| f != 0.0), "no image pushed");
}

/// Checks the round trip of `scene`'s checkpoint after 40 steps and 30 steps on from it;
/// the wall images' sums at the end.
fn round_trip_and_step_on(scene: &Scene) -> Vec<[f32; 4]> {
    let scene = scene.clone();
    let (mut sim, bytes) = stepped(&scene, 40);
    let checkpoint = Checkpoint::decode(&bytes).unwrap();
    assert_eq!(checkpoint.encode(), bytes);
    assert_eq!(checkpoint.state.step, 40);
    assert_eq!(checkpoint.counters.frame_step, Some(7));
    assert_eq!(checkpoint.history.last.unwrap().0.hits, 4);
    assert_eq!(checkpoint.frames.as_ref().unwrap()[0].2, "target_00000.vtu");

    let mut restart = Restart {
        file: PathBuf::from("restart.bin"),
        checkpoint,
    };
    let mut model = Model::assemble(&scene).unwrap();
    restart.restore(&mut model).unwrap();
    let mut restored = Simulation::on_cpu(model);
    for _ in 0..30 {
        sim.step().unwrap();
        restored.step().unwrap();
    }
    let (a, b) = (sim.model().unwrap(), restored.model().unwrap());
    assert_eq!(a.time.to_bits(), b.time.to_bits());
    assert_eq!(a.dt.to_bits(), b.dt.to_bits());
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.particles.p), bits(&b.particles.p));
    assert_eq!(bits(&a.projectile.nodes.z), bits(&b.projectile.nodes.z));
    assert_eq!(
        a.account.contact_impulse.to_bits(),
        b.account.contact_impulse.to_bits()
    );
    let bits64 = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits64(&a.account.segment_impulse),
        bits64(&b.account.segment_impulse)
    );
    let sums = |m: &Model| {
        m.walls
            .sums
            .iter()
            .flatten()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(sums(a), sums(b));
    a.walls.sums.clone()
}

/// A file cut short, of another kind or version, or changed after it was written is
/// refused, and says which of these it is.
#[test]
fn a_damaged_file_is_refused_by_what_is_wrong() {
    let (_, bytes) = stepped(&smoke(), 2);
    for cut in [0, 5, 8, 13, HEADER, bytes.len() / 2, bytes.len() - 1] {
        let refusal = Checkpoint::decode(&bytes[..cut]).unwrap_err();
        assert!(
            matches!(refusal, Refusal::Truncated { needed, .. } if needed as usize == bytes.len() || cut < HEADER),
            "cut at {cut}: {refusal}"
        );
    }
    let mut other = bytes.clone();
    other[0] = b'X';
    assert_eq!(
        Checkpoint::decode(&other).unwrap_err(),
        Refusal::NotACheckpoint
    );
    let mut other = bytes.clone();
    other[8..12].copy_from_slice(&(VERSION + 1).to_le_bytes());
    assert_eq!(
        Checkpoint::decode(&other).unwrap_err(),
        Refusal::Version { found: VERSION + 1 }
    );
    let mut other = bytes.clone();
    let last = other.len() - 1;
    other[last] ^= 1;
    assert!(matches!(
        Checkpoint::decode(&other).unwrap_err(),
        Refusal::Checksum { .. }
    ));
    let mut other = bytes.clone();
    other.push(0);
    assert!(matches!(
        Checkpoint::decode(&other).unwrap_err(),
        Refusal::Malformed(_)
    ));
}

/// A scene that differs is named by its keys and both values.
#[test]
fn scene_differences_name_the_keys() {
    let there = "name = \"smoke\"  # \nrun.end_time = 2e-5  # s\nrun.cfl = 0.5  # \n";
    let here = "name = \"smoke\"  # \nrun.end_time = 3e-5  # s\nrun.cfl = 0.5  # \n";
    assert_eq!(
        scene_differences(there, here),
        vec!["run.end_time: 2e-5 there, 3e-5 here"]
    );
    assert!(scene_differences(there, there).is_empty());
}
