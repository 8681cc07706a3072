//! The shape of one axisymmetric triangle at its current node positions: what `fem_stress`
//! differentiates over, and what the mesher, the state and the step estimate measure with.

/// Shape data of one triangle at its current position: b_i = z_j − z_m, c_i = r_m − r_j.
#[derive(Clone, Copy, Debug)]
pub struct Geometry {
    pub r: [f32; 3],
    pub z: [f32; 3],
    pub b: [f32; 3],
    pub c: [f32; 3],
    /// 2A = Σ r_i b_i (positive for counter-clockwise nodes).
    pub two_area: f32,
    /// Mean radius r̄.
    pub r_mean: f32,
}

impl Geometry {
    pub fn new(nodes: &[u32; 3], r: &[f32], z: &[f32]) -> Geometry {
        let rr = [
            r[nodes[0] as usize],
            r[nodes[1] as usize],
            r[nodes[2] as usize],
        ];
        let zz = [
            z[nodes[0] as usize],
            z[nodes[1] as usize],
            z[nodes[2] as usize],
        ];
        let b = [zz[1] - zz[2], zz[2] - zz[0], zz[0] - zz[1]];
        let c = [rr[2] - rr[1], rr[0] - rr[2], rr[1] - rr[0]];
        // 2A from the edge vectors (translation invariant, better in f32 than Σ r_i b_i).
        let two_area = (rr[1] - rr[0]) * (zz[2] - zz[0]) - (rr[2] - rr[0]) * (zz[1] - zz[0]);
        Geometry {
            r: rr,
            z: zz,
            b,
            c,
            two_area,
            r_mean: (rr[0] + rr[1] + rr[2]) / 3.0,
        }
    }

    /// Ring volume V = 2π r̄ A.
    pub fn volume(&self) -> f32 {
        std::f32::consts::PI * self.r_mean * self.two_area
    }

    /// Smallest altitude: 2A over the longest edge.
    pub fn min_altitude(&self) -> f32 {
        let mut longest = 0.0f32;
        for k in 0..3 {
            longest = longest.max((self.b[k] * self.b[k] + self.c[k] * self.c[k]).sqrt());
        }
        self.two_area / longest
    }
}
