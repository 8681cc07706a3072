//! VTK frames written off the stepping thread: the run hands a frame's arrays over and steps
//! on while a thread of this module writes its `.vtu` files and `frames.pvd`.
//!
//! At most one frame waits while another is written, so a disk slower than the stepping
//! holds the run back rather than filling memory. A frame the disk refuses ends the writer:
//! nothing after it is written (the collection names only frames that exist), and the run
//! learns of it at its next look ([`FrameWriter::check`], every step), at the next frame it
//! hands over, or when it finishes.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, SyncSender};
use std::thread::JoinHandle;

use super::vtk::{self, Collection, Vtu};

/// One frame: its number, the step and time it shows, and its parts.
pub struct Frame {
    pub number: usize,
    pub step: u64,
    /// s
    pub time: f64,
    pub parts: Vec<Part>,
}

/// A part of a frame: its file (`target_00003.vtu`), its part number in the collection, and
/// its grid.
pub struct Part {
    pub file: String,
    pub index: usize,
    pub grid: Vtu,
}

impl Frame {
    /// Writes each part into `dir` and lists it in `pvd`, stopping at the first refusal.
    pub fn write(&self, dir: &Path, pvd: &mut Collection) -> io::Result<()> {
        for part in &self.parts {
            vtk::write_vtu(&dir.join(&part.file), &part.grid)?;
            pvd.add(self.time, part.index, &part.file)?;
        }
        Ok(())
    }
}

/// A frame the disk refused: which, the step and time it shows, and the error (naming the
/// file).
#[derive(Debug)]
pub struct Refused {
    pub frame: usize,
    pub step: u64,
    /// s
    pub time: f64,
    pub error: io::Error,
}

/// The thread that writes the frames handed to it, in order.
pub struct FrameWriter {
    /// Frames to write; `None` once closed.
    frames: Option<SyncSender<Frame>>,
    /// The thread, until joined: it ends when the frames are closed or one is refused, and
    /// gives back the collection with what it wrote.
    thread: Option<JoinHandle<(Collection, Result<(), Refused>)>>,
    /// The collection, once the thread has given it back.
    pvd: Option<Collection>,
}

impl FrameWriter {
    /// A writer of frames into `dir`, listed in `pvd` (which may list earlier frames).
    pub fn spawn(dir: PathBuf, mut pvd: Collection) -> FrameWriter {
        // One frame waits while one is written.
        let (frames, received) = sync_channel::<Frame>(1);
        let thread = std::thread::spawn(move || {
            for frame in received {
                if let Err(error) = frame.write(&dir, &mut pvd) {
                    let refused = Refused {
                        frame: frame.number,
                        step: frame.step,
                        time: frame.time,
                        error,
                    };
                    return (pvd, Err(refused));
                }
            }
            (pvd, Ok(()))
        });
        FrameWriter {
            frames: Some(frames),
            thread: Some(thread),
            pvd: None,
        }
    }

    /// Hands `frame` over, waiting while another frame waits; an earlier frame's refusal
    /// instead (`frame` is then dropped, as is every frame after a refusal was returned).
    pub fn send(&mut self, frame: Frame) -> Result<(), Refused> {
        self.check()?;
        match &self.frames {
            Some(frames) if frames.send(frame).is_ok() => Ok(()),
            // The thread ended, or had been joined: it refused a frame.
            _ => self.join(),
        }
    }

    /// The refusal of a frame handed over earlier, if the writer has stopped on one; does not
    /// wait.
    pub fn check(&mut self) -> Result<(), Refused> {
        if self.thread.as_ref().is_some_and(JoinHandle::is_finished) {
            return self.join();
        }
        Ok(())
    }

    /// Waits for every frame handed over to be written, or for the first refused.
    pub fn finish(mut self) -> Result<(), Refused> {
        self.join()
    }

    /// Waits for every frame handed over to be written, and gives back the collection that
    /// lists them (a checkpoint records it; a new writer goes on from it).
    pub fn drain(mut self) -> Result<Collection, Refused> {
        self.join()?;
        // Joined without a refusal: the thread gave the collection back.
        Ok(self.pvd.take().unwrap_or_default())
    }

    fn join(&mut self) -> Result<(), Refused> {
        // Closing the channel ends the thread once it has written what it holds.
        self.frames = None;
        match self.thread.take().map(JoinHandle::join) {
            None => Ok(()),
            Some(Ok((pvd, written))) => {
                self.pvd = Some(pvd);
                written
            }
            Some(Err(panic)) => std::panic::resume_unwind(panic),
        }
    }
}

impl Drop for FrameWriter {
    /// A run that ends by an error still waits for the frames it handed over, so that none is
    /// left half-written (as `<name>.partial`) when the process exits.
    fn drop(&mut self) {
        self.frames = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(number: usize) -> Frame {
        Frame {
            number,
            step: 10 * number as u64,
            time: 1e-6 * number as f64,
            parts: vec![Part {
                file: format!("part_{number:05}.vtu"),
                index: 0,
                grid: Vtu {
                    r: vec![0.0, 1.0],
                    z: vec![2.0, 3.0],
                    point_data: vec![("n".into(), vec![number as f32; 2])],
                    ..Vtu::default()
                },
            }],
        }
    }

    /// Frames come out in order and listed; a refused one names its frame, step and time, and
    /// nothing after it is written or listed.
    #[cfg(unix)]
    #[test]
    fn frames_are_written_in_order_until_one_is_refused() {
        let dir = std::env::temp_dir().join(format!("penetrate-frames-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::os::unix::fs::symlink("/dev/full", dir.join("part_00003.vtu.partial")).unwrap();
        let mut writer = FrameWriter::spawn(dir.clone(), Collection::new(dir.join("f.pvd")));
        let mut refused = None;
        for n in 0..6 {
            if let Err(r) = writer.send(frame(n)) {
                refused = Some(r);
                break;
            }
        }
        let refused = match refused {
            Some(r) => r,
            None => writer.finish().unwrap_err(),
        };
        assert_eq!((refused.frame, refused.step, refused.time), (3, 30, 3e-6));
        assert_eq!(refused.error.kind(), io::ErrorKind::StorageFull);
        assert!(refused.error.to_string().contains("part_00003.vtu"));
        for n in 0..3 {
            let grid = vtk::read_vtu(&dir.join(format!("part_{n:05}.vtu"))).unwrap();
            assert_eq!(grid.point_field("n"), Some(&[n as f32; 2][..]));
        }
        assert!(!dir.join("part_00004.vtu").exists());
        let pvd = std::fs::read_to_string(dir.join("f.pvd")).unwrap();
        assert_eq!(pvd.matches("<DataSet").count(), 3, "{pvd}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
