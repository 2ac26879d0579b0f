//! Annotation noise: Gaussian jitter of every clicked point of a scene.

use rand::Rng;
use rand_distr::{Distribution, Normal};

use crate::scene::Scene;

/// Add Gaussian noise of standard deviation `sigma_px` to every clicked point of a scene: box
/// corners and tops, footprint vertices, floor corners, and the end points of vanishing-point
/// lines. A vanishing point given as a point is left alone: it is not clicked but computed, often
/// far outside the image, where a pixel of error means nothing; its error comes from the lines
/// it is fitted to. The clicked points are jittered in that order, so a scene's object and floor
/// noise does not depend on whether it carries vanishing-point lines.
pub fn add_noise(scene: &mut Scene, sigma_px: f64, rng: &mut impl Rng) {
    if sigma_px <= 0.0 {
        return;
    }
    let Ok(normal) = Normal::new(0.0, sigma_px) else {
        return;
    };
    let mut jitter = |p: &mut [f64]| {
        for v in p {
            *v += normal.sample(rng);
        }
    };
    for o in &mut scene.objects {
        if let Some(b) = &mut o.base {
            for p in b.points_mut() {
                jitter(p);
            }
        }
        if let Some(f) = &mut o.footprint {
            for p in f {
                jitter(p);
            }
        }
        if let Some(t) = &mut o.top {
            for p in t.corners.points_mut() {
                jitter(p);
            }
            if let Some(p) = &mut t.point {
                jitter(p);
            }
        }
    }
    for p in &mut scene.floor {
        jitter(p);
    }
    for vp in &mut scene.vanishing_points {
        for l in &mut vp.lines {
            jitter(l);
        }
    }
}
