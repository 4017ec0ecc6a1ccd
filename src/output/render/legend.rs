//! The picture's colour map, colour bars and length scale.

use super::{Area, AreaResult};
use plotters::prelude::*;

/// Stops of the colour map: blue (the low end), cyan, green, yellow, red (the high end).
const STOPS: [(u8, u8, u8); 5] = [(40, 60, 200), (0, 170, 220), (40, 170, 60), (235, 200, 0), (210, 30, 30)];

/// The colour of `t` in [0, 1] (clamped): linear between the five stops of [`STOPS`]. Bolts are
/// coloured by their axial force and mesh elements by their stress through it, each with a
/// colour bar ([`colour_bar`]) giving the values of its ends.
pub fn colour_map(t: f64) -> RGBColor {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let x = t * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A value range for the colour map: `lo..hi`, never empty.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub lo: f64,
    pub hi: f64,
}

impl Range {
    /// The range of `values`, widened to hold `also` (e.g. 0 for forces); a single value `v`
    /// spans v..v + max(|v|, 1) so that it takes the low colour.
    pub fn of(values: impl Iterator<Item = f64>, also: Option<f64>) -> Range {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.chain(also).filter(|v| v.is_finite()) {
            (lo, hi) = (lo.min(v), hi.max(v));
        }
        if lo > hi {
            return Range { lo: 0.0, hi: 1.0 };
        }
        if hi <= lo {
            hi = lo + lo.abs().max(1.0);
        }
        Range { lo, hi }
    }

    /// Where `v` lies in the range, 0 at `lo` and 1 at `hi`.
    pub fn at(&self, v: f64) -> f64 {
        (v - self.lo) / (self.hi - self.lo)
    }

    pub fn colour(&self, v: f64) -> RGBColor {
        colour_map(self.at(v))
    }
}

/// Text of a legend number: plain for moderate magnitudes, else scientific.
fn label(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-2..1e5).contains(&a) {
        format!("{}", (v * 1e3).round() / 1e3)
    } else {
        format!("{v:.3e}")
    }
}

/// A vertical colour bar in the box `(x, top)`..`(x + 18, bottom)`: the range's high end at the
/// top, its title above it, the end values beside it.
pub fn colour_bar<'a>(
    root: &Area<'a>,
    range: Range,
    title: &str,
    x: i32,
    top: i32,
    bottom: i32,
) -> AreaResult<'a> {
    let font = ("sans-serif", 14).into_font();
    root.draw(&Text::new(title.to_owned(), (x - 60, top - 22), font.clone()))?;
    let n = (bottom - top).max(1);
    for k in 0..n {
        let t = 1.0 - k as f64 / (n - 1).max(1) as f64;
        root.draw(&Rectangle::new([(x, top + k), (x + 18, top + k + 1)], colour_map(t).filled()))?;
    }
    root.draw(&Rectangle::new([(x, top), (x + 18, bottom)], BLACK.stroke_width(1)))?;
    root.draw(&Text::new(label(range.hi), (x + 22, top - 6), font.clone()))?;
    root.draw(&Text::new(label(range.lo), (x + 22, bottom - 8), font))?;
    Ok(())
}

/// A length scale at the picture's bottom left: a bar of a round length (1, 2 or 5 × 10^k m)
/// near a fifth of the picture's width, `scale` pixels per metre.
pub fn scale_bar<'a>(root: &Area<'a>, scale: f64, size: (u32, u32)) -> AreaResult<'a> {
    let want = 0.2 * size.0 as f64 / scale;
    let p = 10f64.powf(want.log10().floor());
    let len = [5.0, 2.0, 1.0].into_iter().map(|m| m * p).find(|l| *l <= want).unwrap_or(p);
    let (x, y) = (12, size.1 as i32 - 16);
    let px = (len * scale).round() as i32;
    let bar = BLACK.stroke_width(2);
    root.draw(&PathElement::new(vec![(x, y), (x + px, y)], bar))?;
    for end in [x, x + px] {
        root.draw(&PathElement::new(vec![(end, y - 5), (end, y + 5)], bar))?;
    }
    root.draw(&Text::new(format!("{} m", label(len)), (x + px + 8, y - 8), ("sans-serif", 14)))?;
    Ok(())
}
