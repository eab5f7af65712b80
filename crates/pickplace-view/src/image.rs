//! RGBA8 images, colours, PNG encoding and image montages.

use crate::error::{Error, Result};
use pickplace_geometry::export::write_atomic;
use std::path::Path;

/// An sRGB colour, 8 bits per channel (opaque).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Colour {
    /// Red.
    pub r: u8,
    /// Green.
    pub g: u8,
    /// Blue.
    pub b: u8,
}

impl Colour {
    /// White.
    pub const WHITE: Colour = Colour::new(255, 255, 255);
    /// Black.
    pub const BLACK: Colour = Colour::new(0, 0, 0);
    /// Light grey, the default object colour.
    pub const GREY: Colour = Colour::new(170, 170, 170);
    /// Red (x axes, targets).
    pub const RED: Colour = Colour::new(220, 40, 40);
    /// Green (y axes).
    pub const GREEN: Colour = Colour::new(40, 180, 60);
    /// Blue (z axes, normals).
    pub const BLUE: Colour = Colour::new(40, 90, 220);
    /// Orange (highlights).
    pub const ORANGE: Colour = Colour::new(245, 150, 30);

    /// A colour from its sRGB channels.
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        Self { r, g, b }
    }

    /// The `index`-th colour of an endless palette of well-separated hues, for cluster pictures.
    ///
    /// Hues step by the golden angle so that neighbouring indices differ strongly; saturation
    /// and value cycle with a short period so that far-apart indices with close hues still
    /// differ. Deterministic.
    pub fn palette(index: usize) -> Self {
        const GOLDEN_TURN: f64 = 0.381_966_011_250_105_1;
        let hue = (index as f64 * GOLDEN_TURN).fract();
        let saturation = [0.65, 0.45, 0.8][index % 3];
        let value = [0.92, 0.78, 0.62][(index / 3) % 3];
        Self::from_hsv(hue, saturation, value)
    }

    /// A colour from hue (turns, wrapped into [0, 1)), saturation and value (clamped to [0, 1]).
    pub fn from_hsv(hue: f64, saturation: f64, value: f64) -> Self {
        let h = hue.rem_euclid(1.0) * 6.0;
        let s = saturation.clamp(0.0, 1.0);
        let v = value.clamp(0.0, 1.0);
        let c = v * s;
        let x = c * (1.0 - ((h % 2.0) - 1.0).abs());
        let (r, g, b) = match h as u32 {
            0 => (c, x, 0.0),
            1 => (x, c, 0.0),
            2 => (0.0, c, x),
            3 => (0.0, x, c),
            4 => (x, 0.0, c),
            _ => (c, 0.0, x),
        };
        let m = v - c;
        Self::new(unit_to_u8(r + m), unit_to_u8(g + m), unit_to_u8(b + m))
    }

    /// The colour in linear light, each channel in [0, 1] (the sRGB transfer function undone).
    pub fn to_linear(self) -> [f64; 3] {
        [
            srgb_to_linear(self.r),
            srgb_to_linear(self.g),
            srgb_to_linear(self.b),
        ]
    }

    /// The colour of linear-light channels (clamped to [0, 1]).
    pub fn from_linear(linear: [f64; 3]) -> Self {
        Self::new(
            linear_to_srgb(linear[0]),
            linear_to_srgb(linear[1]),
            linear_to_srgb(linear[2]),
        )
    }
}

fn unit_to_u8(x: f64) -> u8 {
    // Clamped to [0, 255] before the cast, so the cast is exact.
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn srgb_to_linear(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(x: f64) -> u8 {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    let c = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    unit_to_u8(c)
}

/// An image of 8-bit RGBA pixels, rows top to bottom, four bytes per pixel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    width: u32,
    height: u32,
    rgba: Vec<u8>,
}

/// Largest width or height accepted (pixels).
pub const MAX_IMAGE_SIDE: u32 = 16_384;
/// Largest number of pixels of an image (64 Mpx, 8192x8192): an image takes 4 bytes a pixel,
/// and [`render`](crate::render) with supersampling 36 bytes more (a 16384x16384 picture
/// needed 9.5 GB; one at this limit about 2.7 GB).
pub const MAX_IMAGE_PIXELS: u64 = 8192 * 8192;

/// Checks an image size against [`MAX_IMAGE_SIDE`] and [`MAX_IMAGE_PIXELS`], before any
/// buffer of that size is allocated.
///
/// # Errors
/// [`Error::InvalidParameter`] when a side is 0 or above [`MAX_IMAGE_SIDE`];
/// [`Error::ImageTooLarge`] when `width * height` is above [`MAX_IMAGE_PIXELS`].
pub fn check_image_size(width: u32, height: u32) -> Result<()> {
    check_side("width", width)?;
    check_side("height", height)?;
    let pixels = u64::from(width) * u64::from(height);
    if pixels > MAX_IMAGE_PIXELS {
        return Err(Error::ImageTooLarge {
            width: u64::from(width),
            height: u64::from(height),
            pixels,
            limit: MAX_IMAGE_PIXELS,
        });
    }
    Ok(())
}

impl Image {
    /// An image filled with one opaque colour.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when a side is 0 or above [`MAX_IMAGE_SIDE`];
    /// [`Error::ImageTooLarge`] above [`MAX_IMAGE_PIXELS`].
    pub fn new(width: u32, height: u32, fill: Colour) -> Result<Self> {
        check_image_size(width, height)?;
        let pixel = [fill.r, fill.g, fill.b, 255];
        let rgba = pixel.repeat(width as usize * height as usize);
        Ok(Self {
            width,
            height,
            rgba,
        })
    }

    /// An image from raw RGBA bytes.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a bad side, or when `rgba` is not `4 * width * height`
    /// bytes long; [`Error::ImageTooLarge`] above [`MAX_IMAGE_PIXELS`].
    pub fn from_rgba(width: u32, height: u32, rgba: Vec<u8>) -> Result<Self> {
        check_image_size(width, height)?;
        if rgba.len() != 4 * width as usize * height as usize {
            return Err(Error::InvalidParameter {
                name: "rgba.len()",
                value: rgba.len() as f64,
                reason: "must be 4 * width * height",
            });
        }
        Ok(Self {
            width,
            height,
            rgba,
        })
    }

    /// Width (pixels).
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height (pixels).
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The RGBA bytes, rows top to bottom.
    pub fn as_rgba(&self) -> &[u8] {
        &self.rgba
    }

    /// The pixel at column `x`, row `y` (0 = top), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        Some([
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ])
    }

    /// Sets the pixel at column `x`, row `y`; does nothing outside the image.
    pub fn set_pixel(&mut self, x: u32, y: u32, rgba: [u8; 4]) {
        if x < self.width && y < self.height {
            let i = 4 * (y as usize * self.width as usize + x as usize);
            self.rgba[i..i + 4].copy_from_slice(&rgba);
        }
    }

    /// Encodes the image as a PNG (8-bit RGBA, deterministic: same pixels, same bytes).
    ///
    /// # Errors
    /// [`Error::PngEncode`] if the encoder fails (it does not for a valid image).
    pub fn encode_png(&self) -> Result<Vec<u8>> {
        let mut out = Vec::with_capacity(self.rgba.len() / 4 + 1024);
        let wrap = |source| Error::PngEncode {
            width: self.width,
            height: self.height,
            source,
        };
        let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        let mut writer = encoder.write_header().map_err(wrap)?;
        writer.write_image_data(&self.rgba).map_err(wrap)?;
        writer.finish().map_err(wrap)?;
        Ok(out)
    }

    /// Writes the image as a PNG file, atomically: the bytes go to a temporary file in the same
    /// directory, which is then renamed over `path`, so `path` is never half-written.
    ///
    /// # Errors
    /// [`Error::PngEncode`], or [`Error::Write`] naming `path`.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        let bytes = self.encode_png()?;
        Ok(write_atomic(path, &bytes)?)
    }
}

fn check_side(name: &'static str, side: u32) -> Result<()> {
    if side == 0 || side > MAX_IMAGE_SIDE {
        return Err(Error::InvalidParameter {
            name,
            value: f64::from(side),
            reason: "image sides must be between 1 and 16384 pixels",
        });
    }
    Ok(())
}

/// Options of [`montage`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MontageOptions {
    /// Number of columns; 0 chooses the smallest `c` with `c * c >= n` (default: 0).
    pub columns: usize,
    /// Gap between cells and around the border (pixels) (default: 4).
    pub gap: u32,
    /// Colour of the gaps and of cell space an image does not cover (default: white).
    pub background: Colour,
}

impl Default for MontageOptions {
    fn default() -> Self {
        Self {
            columns: 0,
            gap: 4,
            background: Colour::WHITE,
        }
    }
}

/// Tiles images into one, row by row, in a grid without labels. Every cell is as large as the
/// largest image; smaller images are centred in their cells.
///
/// # Errors
/// [`Error::InvalidParameter`] when `images` is empty or the result would exceed
/// [`MAX_IMAGE_SIDE`].
pub fn montage(images: &[Image], options: &MontageOptions) -> Result<Image> {
    if images.is_empty() {
        return Err(Error::InvalidParameter {
            name: "images.len()",
            value: 0.0,
            reason: "a montage needs at least one image",
        });
    }
    let n = images.len();
    let columns = if options.columns == 0 {
        (1..=n).find(|c| c * c >= n).unwrap_or(n)
    } else {
        options.columns.min(n)
    };
    let rows = n.div_ceil(columns);
    let cell_w = u64::from(images.iter().map(Image::width).max().unwrap_or(1));
    let cell_h = u64::from(images.iter().map(Image::height).max().unwrap_or(1));
    let gap = u64::from(options.gap);
    let total_w = columns as u64 * (cell_w + gap) + gap;
    let total_h = rows as u64 * (cell_h + gap) + gap;
    let side = |name: &'static str, v: u64| -> Result<u32> {
        u32::try_from(v)
            .ok()
            .filter(|&v| v <= MAX_IMAGE_SIDE)
            .ok_or(Error::InvalidParameter {
                name,
                value: v as f64,
                reason: "the montage would exceed 16384 pixels",
            })
    };
    let mut out = Image::new(
        side("montage width", total_w)?,
        side("montage height", total_h)?,
        options.background,
    )?;
    for (k, image) in images.iter().enumerate() {
        let (col, row) = ((k % columns) as u64, (k / columns) as u64);
        let x0 = gap + col * (cell_w + gap) + (cell_w - u64::from(image.width)) / 2;
        let y0 = gap + row * (cell_h + gap) + (cell_h - u64::from(image.height)) / 2;
        let row_bytes = 4 * image.width as usize;
        for y in 0..image.height as usize {
            let src = &image.rgba[y * row_bytes..(y + 1) * row_bytes];
            let dst_start = 4 * ((y0 as usize + y) * out.width as usize + x0 as usize);
            out.rgba[dst_start..dst_start + row_bytes].copy_from_slice(src);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_over_the_pixel_limit_are_refused_before_allocating() {
        // Regression (issue 18): 16384x16384 needed 9.5 GB to render.
        let e = Image::new(16_384, 16_384, Colour::WHITE).expect_err("refused");
        assert!(
            e.to_string()
                .contains("16384x16384 pixels is 268435456 pixels, over the limit of 67108864"),
            "{e}"
        );
        assert!(check_image_size(8192, 8192).is_ok());
        assert!(check_image_size(8193, 8192).is_err());
        assert!(check_image_size(16_384, 4096).is_ok());
        assert!(check_image_size(0, 1).is_err());
        // A montage within the side limit but over the pixel limit: 840 rows of 16000x1.
        let strips = vec![Image::new(16_000, 1, Colour::WHITE).expect("image"); 840];
        let options = MontageOptions {
            columns: 1,
            ..MontageOptions::default()
        };
        assert!(matches!(
            montage(&strips, &options),
            Err(Error::ImageTooLarge {
                width: 16_008,
                height: 4204,
                ..
            })
        ));
        assert!(montage(&strips[..800], &options).is_ok());
    }

    #[test]
    fn srgb_round_trips_through_linear() {
        for v in 0..=255u8 {
            let c = Colour::new(v, 255 - v, v / 2);
            assert_eq!(Colour::from_linear(c.to_linear()), c);
        }
    }

    #[test]
    fn palette_neighbours_differ() {
        for i in 0..50 {
            let (a, b) = (Colour::palette(i), Colour::palette(i + 1));
            let d = (i32::from(a.r) - i32::from(b.r)).abs()
                + (i32::from(a.g) - i32::from(b.g)).abs()
                + (i32::from(a.b) - i32::from(b.b)).abs();
            assert!(d > 40, "palette {i} and {} too close: {a:?} {b:?}", i + 1);
        }
    }

    #[test]
    fn bad_sizes_are_errors() {
        assert!(Image::new(0, 10, Colour::WHITE).is_err());
        assert!(Image::new(10, MAX_IMAGE_SIDE + 1, Colour::WHITE).is_err());
        assert!(Image::from_rgba(2, 2, vec![0; 15]).is_err());
        assert!(montage(&[], &MontageOptions::default()).is_err());
    }

    #[test]
    fn montage_places_cells_row_by_row() {
        let colours = [Colour::RED, Colour::GREEN, Colour::BLUE];
        let images: Vec<Image> = colours
            .iter()
            .map(|&c| Image::new(10, 6, c).expect("valid size"))
            .collect();
        let options = MontageOptions {
            columns: 2,
            gap: 2,
            background: Colour::BLACK,
        };
        let m = montage(&images, &options).expect("valid montage");
        assert_eq!((m.width(), m.height()), (2 * 12 + 2, 2 * 8 + 2));
        assert_eq!(m.pixel(0, 0), Some([0, 0, 0, 255]));
        assert_eq!(m.pixel(2, 2), Some([220, 40, 40, 255]));
        assert_eq!(m.pixel(14, 2), Some([40, 180, 60, 255]));
        assert_eq!(m.pixel(2, 10), Some([40, 90, 220, 255]));
        assert_eq!(
            m.pixel(14, 10),
            Some([0, 0, 0, 255]),
            "empty cell keeps the background"
        );
    }
}
