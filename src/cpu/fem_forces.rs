//! `fem_forces`: per node, gather the forces of its elements through the node → element CSR
//! (a gather, never a scatter: no float atomics on the GPU, the same bits every run).

use rayon::prelude::*;

use crate::state::{Elements, Nodes};

pub fn run(nodes: &mut Nodes, elements: &Elements) {
    let Nodes {
        fr,
        fz,
        elem_offsets,
        elem_refs,
        ..
    } = nodes;
    fr.par_iter_mut()
        .zip(fz.par_iter_mut())
        .enumerate()
        .for_each(|(n, (fr, fz))| {
            let mut sum = [0.0f32; 2];
            for &code in &elem_refs[elem_offsets[n] as usize..elem_offsets[n + 1] as usize] {
                let f = &elements.force[(code / 3) as usize];
                let local = (code % 3) as usize;
                sum[0] += f[2 * local];
                sum[1] += f[2 * local + 1];
            }
            *fr = sum[0];
            *fz = sum[1];
        });
}
