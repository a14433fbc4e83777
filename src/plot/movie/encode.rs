//! GIF encoding of RGB frames: one global 256-colour palette for the whole movie, learnt by
//! NeuQuant (the `color_quant` crate) from the pixels of a few frames spread over the movie, in
//! which the body's pixels are over-represented (they are few but carry the shading); a
//! 32x32x32 lookup table from colour to palette index; the frames rendered, indexed and
//! LZW-compressed in parallel (the `gif` crate's pre-encoded frames), keeping only the
//! compressed frames in memory, then written in order.

use super::super::{draw_err, PlotError};
use rayon::prelude::*;
use std::io::Write;

/// One rendered frame: RGB pixels and a mask of the pixels showing the body.
pub(super) struct Rgb {
    pub rgb: Vec<u8>,
    pub body: Vec<bool>,
}

/// Pixels sampled for the palette: about this many from the sample frames, plus the body's.
const SAMPLE: usize = 120_000;
/// Frames the palette is learnt from.
const PALETTE_FRAMES: usize = 8;

/// The palette (RGB triples) learnt from the frames.
fn palette(frames: &[Rgb]) -> color_quant::NeuQuant {
    let px: usize = frames.iter().map(|f| f.body.len()).sum();
    let stride = (px / SAMPLE).max(1);
    let body_stride = (stride / 8).max(1);
    let mut sample: Vec<u8> = Vec::with_capacity(4 * 2 * SAMPLE);
    let mut k = 0usize;
    for f in frames {
        for (i, &b) in f.body.iter().enumerate() {
            k += 1;
            if k.is_multiple_of(stride) || (b && k.is_multiple_of(body_stride)) {
                sample.extend_from_slice(&f.rgb[3 * i..3 * i + 3]);
                sample.push(255);
            }
        }
    }
    if sample.is_empty() {
        sample.extend_from_slice(&[0, 0, 0, 255]);
    }
    color_quant::NeuQuant::new(10, 256, &sample)
}

/// Write `n` frames, frame `k` drawn by `render(k)`, as an endlessly looping GIF: `delay`
/// between frames (hundredths of a second), `last_delay` on the last frame. Returns the bytes
/// written.
pub(super) fn write_gif(
    out: &mut dyn Write,
    size: (u32, u32),
    n: usize,
    render: &(dyn Fn(usize) -> Result<Rgb, PlotError> + Sync),
    delay: u16,
    last_delay: u16,
) -> Result<usize, PlotError> {
    let (w, h) = (size.0 as u16, size.1 as u16);
    let m = PALETTE_FRAMES.min(n);
    let picks: Vec<usize> = (0..m).map(|j| j * (n - 1) / (m - 1).max(1)).collect();
    let sample = picks
        .par_iter()
        .map(|&k| render(k))
        .collect::<Result<Vec<_>, _>>()?;
    let nq = palette(&sample);
    // The sample frames are kept and indexed with the others, not rendered again.
    let mut kept: Vec<Option<Rgb>> = (0..n).map(|_| None).collect();
    for (k, f) in picks.into_iter().zip(sample) {
        kept[k] = Some(f);
    }
    let kept: Vec<std::sync::Mutex<Option<Rgb>>> =
        kept.into_iter().map(std::sync::Mutex::new).collect();
    let pal = nq.color_map_rgb();
    let mut lut = vec![0u8; 32 * 32 * 32];
    for (j, v) in lut.iter_mut().enumerate() {
        let (r, g, b) = (j >> 10, (j >> 5) & 31, j & 31);
        let c = |x: usize| (x * 8 + 4) as u8;
        *v = nq.index_of(&[c(r), c(g), c(b), 255]) as u8;
    }
    let encoded: Vec<gif::Frame<'static>> = (0..n)
        .into_par_iter()
        .map(|k| {
            let taken = kept[k].lock().ok().and_then(|mut g| g.take());
            let f = match taken {
                Some(f) => f,
                None => render(k)?,
            };
            let idx: Vec<u8> = f
                .rgb
                .chunks_exact(3)
                .map(|p| {
                    lut[((p[0] as usize >> 3) << 10)
                        | ((p[1] as usize >> 3) << 5)
                        | (p[2] as usize >> 3)]
                })
                .collect();
            let mut fr = gif::Frame::from_indexed_pixels(w, h, idx, None);
            fr.delay = if k + 1 == n { last_delay } else { delay };
            fr.make_lzw_pre_encoded();
            Ok(fr)
        })
        .collect::<Result<_, PlotError>>()?;
    let mut counter = Counter { inner: out, n: 0 };
    {
        let mut enc = gif::Encoder::new(&mut counter, w, h, &pal).map_err(draw_err)?;
        enc.set_repeat(gif::Repeat::Infinite).map_err(draw_err)?;
        for fr in &encoded {
            enc.write_lzw_pre_encoded_frame(fr).map_err(draw_err)?;
        }
        enc.into_inner().map_err(draw_err)?;
    }
    Ok(counter.n)
}

/// A writer that counts the bytes passed through.
struct Counter<'a> {
    inner: &'a mut dyn Write,
    n: usize,
}

impl Write for Counter<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let k = self.inner.write(buf)?;
        self.n += k;
        Ok(k)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}
