//! What is being aged: the photo, the wall region, the normal map and the
//! wall plane, checked against each other once, here.

use std::sync::Arc;

use image::{GrayImage, RgbImage};

use crate::error::{Error, Result};
use crate::perspective::{self, Quad};
use crate::photo::Photo;

use super::site::Site;

/// The photo and what is known about its wall. Build it with
/// [`Scene::new`] and the `with_` methods, which check every part against
/// the photo.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The photo.
    pub photo: Arc<Photo>,
    /// Wall region, photo-sized, 255 = wall; `None` = the whole photo.
    pub region: Option<Arc<GrayImage>>,
    /// Tangent-space normal map of the wall, photo-sized, for the dust's
    /// per-pixel view and light angles (see [`crate::effects::dust::shade`]).
    pub normals: Option<Arc<RgbImage>>,
    /// The wall plane: a quad on the photo whose corners are a rectangle on
    /// the wall. The effects then run in that plane ([`crate::perspective`]).
    pub quad: Option<Quad>,
    /// The building around the wall: scale, ground, ledges, shelter.
    pub site: Site,
}

impl Scene {
    /// A scene; the region must have the photo's size.
    ///
    /// # Errors
    /// [`Error::MaskSize`] for a mask of another size.
    pub fn new(photo: Photo, region: Option<GrayImage>) -> Result<Scene> {
        Scene::shared(Arc::new(photo), region.map(Arc::new))
    }

    /// [`Scene::new`] from shared buffers (a GUI keeps its photo and mask).
    ///
    /// # Errors
    /// [`Error::MaskSize`] for a mask of another size.
    pub fn shared(photo: Arc<Photo>, region: Option<Arc<GrayImage>>) -> Result<Scene> {
        if let Some(m) = &region
            && m.dimensions() != (photo.width(), photo.height())
        {
            return Err(Error::MaskSize {
                mask_w: m.width(),
                mask_h: m.height(),
                img_w: photo.width(),
                img_h: photo.height(),
            });
        }
        let site = Site::assumed(photo.width());
        Ok(Scene {
            photo,
            region,
            normals: None,
            quad: None,
            site,
        })
    }

    /// The scene with a normal map for the dust.
    ///
    /// # Errors
    /// [`Error::NormalMapSize`] for a map of another size than the photo.
    pub fn with_normals(mut self, normals: RgbImage) -> Result<Scene> {
        let (w, h) = (self.photo.width(), self.photo.height());
        if normals.dimensions() != (w, h) {
            return Err(Error::NormalMapSize {
                map_w: normals.width(),
                map_h: normals.height(),
                img_w: w,
                img_h: h,
            });
        }
        self.normals = Some(Arc::new(normals));
        Ok(self)
    }

    /// The scene in the wall plane of `quad` (photo pixels; `None` = the
    /// photo's own plane).
    ///
    /// # Errors
    /// [`perspective::validate`]'s errors for a bad quad.
    pub fn with_quad(mut self, quad: Option<Quad>) -> Result<Scene> {
        if let Some(q) = &quad {
            perspective::validate(q)?;
        }
        self.quad = quad;
        Ok(self)
    }

    /// The scene with what is known of the building around the wall.
    ///
    /// # Errors
    /// [`Error::MaskSize`] for a shelter map of another size than the photo,
    /// [`Error::Preset`] for a scale that is not a positive number.
    pub fn with_site(mut self, site: Site) -> Result<Scene> {
        if !(site.metres_per_pixel.is_finite() && site.metres_per_pixel > 0.0) {
            return Err(Error::Preset(format!(
                "metres per pixel must be a positive number, not {}",
                site.metres_per_pixel
            )));
        }
        if let Some(s) = &site.shelter
            && s.dimensions() != self.size()
        {
            return Err(Error::MaskSize {
                mask_w: s.width(),
                mask_h: s.height(),
                img_w: self.photo.width(),
                img_h: self.photo.height(),
            });
        }
        self.site = site;
        Ok(self)
    }

    /// The scene at `ow` x `oh` (an animation's frame size): the photo,
    /// region, normals and shelter area-averaged ([`crate::shrink`]), the
    /// quad, ground and ledges scaled, the metres per pixel larger by as
    /// much. Its run at a preset [`Preset::scaled`] the same way is the
    /// preview of the scene's run.
    ///
    /// [`Preset::scaled`]: crate::preset::Preset::scaled
    pub fn scaled(&self, ow: u32, oh: u32) -> Scene {
        use crate::shrink::{buffer_to_size, to_size};
        let (w, h) = self.size();
        let (sx, sy) = (ow as f32 / w.max(1) as f32, oh as f32 / h.max(1) as f32);
        let mut photo = Photo::new(to_size(self.photo.image(), ow, oh));
        photo.icc = self.photo.icc.clone();
        Scene {
            photo: Arc::new(photo),
            region: self
                .region
                .as_ref()
                .map(|r| Arc::new(buffer_to_size(r, ow, oh))),
            normals: self
                .normals
                .as_ref()
                .map(|n| Arc::new(buffer_to_size(n, ow, oh))),
            quad: self.quad.map(|q| q.map(|p| [p[0] * sx, p[1] * sy])),
            site: self.site.scaled((w, h), (ow, oh)),
        }
    }

    /// Photo width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.photo.width(), self.photo.height())
    }

    /// Whether `other` holds the same buffers (not only equal ones): what a
    /// [`super::Cache`] was made for.
    pub fn same_as(&self, other: &Scene) -> bool {
        fn same<T>(a: &Option<Arc<T>>, b: &Option<Arc<T>>) -> bool {
            match (a, b) {
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                (None, None) => true,
                _ => false,
            }
        }
        // The ground line holds NaN where there is none: compare bits.
        fn same_bits(a: &[f32], b: &[f32]) -> bool {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
        }
        Arc::ptr_eq(&self.photo, &other.photo)
            && same(&self.region, &other.region)
            && same(&self.normals, &other.normals)
            && self.quad == other.quad
            && self.site.metres_per_pixel == other.site.metres_per_pixel
            && same_bits(&self.site.ground, &other.site.ground)
            && self.site.ledges == other.site.ledges
            && same(&self.site.shelter, &other.site.shelter)
    }
}
