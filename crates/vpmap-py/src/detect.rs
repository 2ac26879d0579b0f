//! `vpmap.detect`: a photo (a file, or an H x W x 3 / H x W `uint8` array) to its vanishing
//! points, camera and scene, by the vision crate's detector as `vpmap detect` runs it.

use numpy::ndarray::Array2;
use numpy::{PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use vpmap_vision::photo::{PhotoLimits, decode_photo};
use vpmap_vision::scene::{DetectedScene, VP_NAMES, detected_scene};
use vpmap_vision::{DetectOptions, Detection, LensOption};

use crate::convert::{as_path, error, json_text_to_py, shown};

/// The expected array forms, named in messages.
const FORMS: &str = "a uint8 array of shape (height, width, 3) (RGB) or (height, width) (grey)";

/// An image from a `uint8` array, any memory order.
fn image_from_array(obj: &Bound<'_, PyAny>) -> PyResult<image::DynamicImage> {
    let py = obj.py();
    let array = py
        .import("numpy")?
        .getattr("asarray")?
        .call1((obj,))
        .map_err(|e| error(format!("{} is not an image: {e}; give {FORMS}", shown(obj))))?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    let dtype = array.getattr("dtype")?.str()?.to_string();
    let refuse = || {
        error(format!(
            "an image array of shape {shape:?} and dtype {dtype} is not an image; give {FORMS}"
        ))
    };
    let too_large = |w: usize, h: usize| {
        error(format!(
            "an image of {w} x {h} pixels is too large (at most {} on a side)",
            vpmap_vision::MAX_SIDE_PX
        ))
    };
    match shape[..] {
        [h, w, 3] => {
            let typed = array
                .cast::<numpy::PyArray3<u8>>()
                .map_err(|_| refuse())?
                .readonly();
            let pixels: Vec<u8> = typed.as_array().iter().copied().collect();
            let (w32, h32) = (
                u32::try_from(w).map_err(|_| too_large(w, h))?,
                u32::try_from(h).map_err(|_| too_large(w, h))?,
            );
            image::RgbImage::from_raw(w32, h32, pixels)
                .map(image::DynamicImage::ImageRgb8)
                .ok_or_else(refuse)
        }
        [h, w] => {
            let typed = array
                .cast::<PyArray2<u8>>()
                .map_err(|_| refuse())?
                .readonly();
            let pixels: Vec<u8> = typed.as_array().iter().copied().collect();
            let (w32, h32) = (
                u32::try_from(w).map_err(|_| too_large(w, h))?,
                u32::try_from(h).map_err(|_| too_large(w, h))?,
            );
            image::GrayImage::from_raw(w32, h32, pixels)
                .map(image::DynamicImage::ImageLuma8)
                .ok_or_else(refuse)
        }
        _ => Err(refuse()),
    }
}

/// Find a photo's vanishing points and camera, as ``vpmap detect`` does.
///
/// ``image`` is a JPEG or PNG file's path, or a ``uint8`` array of shape (height, width, 3)
/// (RGB) or (height, width) (grey). ``focal_px`` and ``principal_point`` give a known camera
/// (default: estimated); ``max_side`` the working size, pixels; ``two_point_tolerance`` the
/// angle, degrees, within which vertical edges make the photo two-point; ``lens`` is
/// ``"estimate"`` (default: the division model's k from the edges), ``"none"`` (a pinhole
/// photo) or a known k. Returns a
/// ``Detection``; its ``scene()`` is the scene file ``vpmap detect`` writes. The GIL is
/// released while it runs. Raises ``VpmapError`` with the message ``vpmap detect`` prints.
#[pyfunction]
#[pyo3(signature = (image, *, focal_px=None, principal_point=None, max_side=None, two_point_tolerance=None, lens=None))]
pub fn detect(
    py: Python<'_>,
    image: &Bound<'_, PyAny>,
    focal_px: Option<f64>,
    principal_point: Option<(f64, f64)>,
    max_side: Option<u32>,
    two_point_tolerance: Option<f64>,
    lens: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyDetection> {
    let defaults = DetectOptions::default();
    let lens = match lens {
        None => LensOption::Estimate,
        Some(v) if v.is_none() => LensOption::Estimate,
        Some(v) => {
            if let Ok(text) = v.extract::<String>() {
                match text.as_str() {
                    "estimate" => LensOption::Estimate,
                    "none" => LensOption::Pinhole,
                    other => {
                        return Err(error(format!(
                            "lens {other:?} is not \"estimate\", \"none\" or a division-model k (a number within -1 to 1)"
                        )));
                    }
                }
            } else {
                let k: f64 = v.extract().map_err(|_| {
                    error("lens must be \"estimate\", \"none\" or a division-model k (a number within -1 to 1)")
                })?;
                LensOption::Known(k)
            }
        }
    };
    let mut opts = DetectOptions {
        focal_px,
        principal_point_px: principal_point.map(|(x, y)| [x, y]),
        max_side_px: max_side.unwrap_or(defaults.max_side_px),
        two_point_tolerance_deg: two_point_tolerance.unwrap_or(defaults.two_point_tolerance_deg),
        lens,
        ..defaults
    };
    let is_text = image.is_instance_of::<pyo3::types::PyString>();
    let (picture, name) = match as_path(image) {
        Some(path) if is_text || !image.hasattr("__array_interface__")? => {
            let bytes =
                vpmap_files::read_bytes(&path, vpmap_files::Format::Photo).map_err(error)?;
            let photo = py
                .detach(|| decode_photo(&bytes, &PhotoLimits::default()))
                .map_err(|e| error(format!("{}: {e}", path.display())))?;
            // The EXIF focal length as a prior, as `vpmap detect` uses it (an unusable one is
            // left out here; the command line says why).
            if focal_px.is_none() {
                opts.focal_prior = photo.exif_focal_prior().ok().flatten();
            }
            (photo.image, path.display().to_string())
        }
        _ => (image_from_array(image)?, "the image".to_owned()),
    };
    let found = py.detach(|| {
        let det = vpmap_vision::detect(&picture, &opts)
            .map_err(|e| format!("no vanishing points found in {name}: {e}"))?;
        let scene = detected_scene(&det)
            .map_err(|e| format!("no usable vanishing points in {name}: {e}"))?;
        Ok::<_, String>((det, scene))
    });
    let (det, scene) = found.map_err(error)?;
    Ok(PyDetection { det, scene })
}

/// What ``vpmap.detect`` found in a photo: the segments, the vanishing points and the camera.
#[pyclass(frozen, name = "Detection", module = "vpmap")]
pub struct PyDetection {
    det: Detection,
    scene: DetectedScene,
}

#[pymethods]
impl PyDetection {
    /// The vanishing points, one dict each: ``point`` (pixels, or ``None`` at infinity),
    /// ``direction`` (camera frame: x right, y down, z forward), ``vertical``, ``segments``
    /// (indices into ``segments``), ``role`` (the name the scene gives it, or ``None``), and,
    /// for a point the scene writes, ``covariance_deg2`` (its 2 x 2 covariance, degrees squared,
    /// across and radial in the scene's chart, as the scene file holds it), ``sd_deg`` (the
    /// ellipse's largest standard deviation, degrees) and ``edges`` (independent edges behind
    /// it); ``None`` for one not written. ``own_point``: the direction's own vanishing point,
    /// its segments alone not held orthogonal to the other two, a dict of ``point`` (pixels in
    /// the pinhole image, or ``None`` at infinity), ``direction``, ``from_frame_deg`` (its angle
    /// from ``direction``) and ``edges``; ``None`` when the segments do not fix one.
    #[getter]
    fn vanishing_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for (i, vp) in self.det.vanishing_points.iter().enumerate() {
            let d = PyDict::new(py);
            d.set_item("point", vp.point_px.map(|[x, y]| (x, y)))?;
            d.set_item(
                "direction",
                (
                    vp.direction_camera[0],
                    vp.direction_camera[1],
                    vp.direction_camera[2],
                ),
            )?;
            d.set_item("vertical", vp.vertical)?;
            d.set_item("segments", vp.segments.clone())?;
            let role = self
                .scene
                .roles
                .iter()
                .zip(VP_NAMES)
                .find(|(r, _)| **r == i)
                .map(|(_, name)| name);
            d.set_item("role", role)?;
            let cov = self
                .scene
                .roles
                .iter()
                .position(|r| *r == i)
                .and_then(|k| self.scene.covariances[k]);
            d.set_item(
                "covariance_deg2",
                cov.map(|c| {
                    let m = c.covariance_deg2;
                    ((m[0][0], m[0][1]), (m[1][0], m[1][1]))
                }),
            )?;
            d.set_item("sd_deg", cov.map(|c| c.major_sd_deg()))?;
            d.set_item("edges", cov.map(|c| c.edges))?;
            let own = match vp.own_point {
                Some(o) => {
                    let od = PyDict::new(py);
                    od.set_item("point", o.point_px.map(|[x, y]| (x, y)))?;
                    od.set_item(
                        "direction",
                        (
                            o.direction_camera[0],
                            o.direction_camera[1],
                            o.direction_camera[2],
                        ),
                    )?;
                    od.set_item("from_frame_deg", o.from_frame_deg)?;
                    od.set_item("edges", o.edges)?;
                    Some(od)
                }
                None => None,
            };
            d.set_item("own_point", own)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// Focal length, pixels.
    #[getter]
    fn focal_px(&self) -> f64 {
        self.det.intrinsics.focal_px
    }

    /// Principal point ``(x, y)``, pixels.
    #[getter]
    fn principal_point(&self) -> (f64, f64) {
        let [x, y] = self.det.intrinsics.principal_point_px;
        (x, y)
    }

    /// The camera the scene gives before any click, with standard deviations (the joint fit
    /// of its vanishing points and the principal point's prior): a dict of ``focal_px``,
    /// ``focal_sd_px``, ``principal_point``, ``principal_point_sd_px`` (``(x, y)``, or ``None``
    /// when the fit held it), ``pitch_deg``, ``pitch_sd_deg``, ``roll_deg``, ``roll_sd_deg``
    /// and ``horizon_sd_px``; ``None`` when that fit fails.
    #[getter]
    fn camera_estimate<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = self.scene.camera_estimate() else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("focal_px", c.focal_px)?;
        d.set_item("focal_sd_px", c.focal_sd_px)?;
        d.set_item(
            "principal_point",
            (c.principal_point_px[0], c.principal_point_px[1]),
        )?;
        d.set_item(
            "principal_point_sd_px",
            c.principal_point_sd_px.map(|[x, y]| (x, y)),
        )?;
        d.set_item("pitch_deg", c.pitch_deg)?;
        d.set_item("pitch_sd_deg", c.pitch_sd_deg)?;
        d.set_item("roll_deg", c.roll_deg)?;
        d.set_item("roll_sd_deg", c.roll_sd_deg)?;
        d.set_item("horizon_sd_px", c.horizon_sd_px)?;
        Ok(Some(d))
    }

    /// The lens distortion the vanishing points were found through: a dict of ``k`` (the
    /// one-parameter division model's applied, barrel negative, 0 when the edges do not show a
    /// lens at 99 %; docs/scene-format.md), ``estimated_k`` (the edges' estimate), ``k_sd`` (0
    /// when given) and ``segments_k_sd`` (the segments' part alone, or ``None``); ``None``
    /// with ``lens="none"``.
    #[getter]
    fn lens<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(l) = &self.det.lens else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("k", l.k())?;
        d.set_item("estimated_k", l.estimated_k)?;
        d.set_item("k_sd", l.k_sd)?;
        d.set_item("segments_k_sd", l.segments_k_sd)?;
        Ok(Some(d))
    }

    /// Whether the focal length was estimated (not given).
    #[getter]
    fn focal_estimated(&self) -> bool {
        self.det.focal_estimated
    }

    /// Whether the photo's edges put the principal point off the image centre, as in a photo
    /// cropped off its centre: the scene then carries the principal point's prior widened, and
    /// ``warnings`` says so.
    #[getter]
    fn principal_point_off_centre(&self) -> bool {
        self.det.principal_point_off_centre
    }

    /// The camera's pitch, degrees (down is positive), as ``vpmap build`` recovers it from
    /// the scene.
    #[getter]
    fn pitch_deg(&self) -> f64 {
        self.scene.calibration.pitch_rad.to_degrees()
    }

    /// The camera's roll, degrees.
    #[getter]
    fn roll_deg(&self) -> f64 {
        self.scene.calibration.roll_rad.to_degrees()
    }

    /// ``"two-point"`` or ``"three-point"`` perspective, as the scene is written.
    #[getter]
    fn perspective(&self) -> &'static str {
        self.scene.perspective.words()
    }

    /// The photo's size ``(width, height)``, pixels.
    #[getter]
    fn image_size(&self) -> (u32, u32) {
        let [w, h] = self.det.image_size_px;
        (w, h)
    }

    /// The line segments as an N x 5 float64 array: ``x0, y0, x1, y1, strength`` (pixels).
    #[getter]
    fn segments<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = self
            .det
            .segments
            .iter()
            .flat_map(|s| {
                [
                    s.start_px[0],
                    s.start_px[1],
                    s.end_px[0],
                    s.end_px[1],
                    s.strength,
                ]
            })
            .collect();
        let array = Array2::from_shape_vec((self.det.segments.len(), 5), flat).map_err(error)?;
        Ok(PyArray2::from_owned_array(py, array))
    }

    /// Warnings ``vpmap detect`` prints: vanishing points resting on few segments, a principal
    /// point the edges put off the image centre (a cropped photo), and the calibration's.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        let mut out: Vec<String> = self
            .scene
            .thinly_supported(&self.det)
            .into_iter()
            .map(|(name, n)| format!("{name} rests on only {n} segments; check it"))
            .collect();
        out.extend(self.scene.off_centre_warning(&self.det));
        out.extend(self.scene.calibration.warnings.iter().cloned());
        out
    }

    /// The scene dict ``vpmap detect`` writes (docs/scene-format.md): the vanishing points
    /// with their segments as evidence, empty ``objects`` and ``floor`` to fill in, then
    /// ``vpmap.build(scene)``.
    fn scene<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_text_to_py(py, &self.scene.json)
    }

    /// The scene file's text, as ``vpmap detect --out`` writes it.
    fn scene_json(&self) -> &str {
        &self.scene.json
    }

    fn __repr__(&self) -> String {
        format!(
            "Detection({} perspective, focal {:.1} px, pitch {:.2} deg, roll {:.2} deg, {} segments)",
            self.scene.perspective.words(),
            self.det.intrinsics.focal_px,
            self.pitch_deg(),
            self.roll_deg(),
            self.det.segments.len()
        )
    }
}
