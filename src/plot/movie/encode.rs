//! GIF encoding of RGB frames: one global 256-colour palette for the whole movie, learnt by
//! NeuQuant (the `color_quant` crate) from the pixels of a few frames spread over the movie, in
//! which the body's pixels are over-represented (they are few but carry the shading); a
//! 32x32x32 lookup table from colour to palette index; the frames rendered, indexed and
//! LZW-compressed in parallel ([`lzw`], a hashed-dictionary encoder about three times faster
//! than the `gif` crate's own, which was the largest cost of a run's movie), keeping only the
//! compressed frames in memory, then written in order by the `gif` crate as pre-encoded
//! frames. After the first, each frame holds only the box of pixels that changed, the
//! unchanged ones in it transparent ([`difference`]; the frames are kept, not disposed).

use super::super::{draw_err, PlotError};
use rayon::prelude::*;
use std::io::Write;

/// One rendered frame: RGB pixels and a mask of the pixels showing the body.
pub(super) struct Rgb {
    pub rgb: Vec<u8>,
    pub body: Vec<bool>,
}

/// Pixels sampled for the palette: about this many from the sample frames, plus the body's.
const SAMPLE: usize = 60_000;
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
    color_quant::NeuQuant::new(10, 255, &sample)
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
    // 255 learnt colours; index 255 is the transparent one of the frame differences.
    let mut pal = nq.color_map_rgb();
    pal.resize(3 * 256, 0);
    let mut lut = vec![0u8; 32 * 32 * 32];
    for (j, v) in lut.iter_mut().enumerate() {
        let (r, g, b) = (j >> 10, (j >> 5) & 31, j & 31);
        let c = |x: usize| (x * 8 + 4) as u8;
        *v = nq.index_of(&[c(r), c(g), c(b), 255]) as u8;
    }
    let indexed: Vec<Vec<u8>> = (0..n)
        .into_par_iter()
        .map(|k| {
            let taken = kept[k].lock().ok().and_then(|mut g| g.take());
            let f = match taken {
                Some(f) => f,
                None => render(k)?,
            };
            Ok(f.rgb
                .chunks_exact(3)
                .map(|p| {
                    lut[((p[0] as usize >> 3) << 10)
                        | ((p[1] as usize >> 3) << 5)
                        | (p[2] as usize >> 3)]
                })
                .collect())
        })
        .collect::<Result<_, PlotError>>()?;
    let encoded: Vec<gif::Frame<'static>> = (0..n)
        .into_par_iter()
        .map(|k| {
            let mut fr = match k {
                0 => gif::Frame {
                    width: w,
                    height: h,
                    buffer: std::borrow::Cow::Owned(lzw(&indexed[0])),
                    ..Default::default()
                },
                _ => difference(&indexed[k - 1], &indexed[k], size.0 as usize),
            };
            fr.delay = if k + 1 == n { last_delay } else { delay };
            fr.dispose = gif::DisposalMethod::Keep;
            fr
        })
        .collect();
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

/// Frame `cur` drawn over `prev` (palette indices, `w` px wide): the box of the changed
/// pixels, the unchanged ones inside it transparent (index 255), LZW-compressed. Most of a
/// movie's ground does not change from one frame to the next, and runs of the transparent
/// index compress fast and small. An unchanged frame is one transparent pixel.
fn difference(prev: &[u8], cur: &[u8], w: usize) -> gif::Frame<'static> {
    let h = cur.len() / w;
    let (mut x0, mut x1, mut y0, mut y1) = (w, 0, h, 0);
    for y in 0..h {
        let (a, b) = (&prev[y * w..(y + 1) * w], &cur[y * w..(y + 1) * w]);
        let Some(first) = a.iter().zip(b).position(|(p, q)| p != q) else {
            continue;
        };
        let last = w
            - 1
            - a.iter()
                .rev()
                .zip(b.iter().rev())
                .position(|(p, q)| p != q)
                .unwrap_or(0);
        x0 = x0.min(first);
        x1 = x1.max(last + 1);
        y0 = y0.min(y);
        y1 = y + 1;
    }
    if y1 == 0 {
        return gif::Frame {
            width: 1,
            height: 1,
            transparent: Some(255),
            buffer: std::borrow::Cow::Owned(lzw(&[255])),
            ..Default::default()
        };
    }
    let mut sub = Vec::with_capacity((x1 - x0) * (y1 - y0));
    for y in y0..y1 {
        let r = y * w + x0..y * w + x1;
        sub.extend(
            prev[r.clone()]
                .iter()
                .zip(&cur[r])
                .map(|(&p, &q)| if p == q { 255 } else { q }),
        );
    }
    gif::Frame {
        left: x0 as u16,
        top: y0 as u16,
        width: (x1 - x0) as u16,
        height: (y1 - y0) as u16,
        transparent: Some(255),
        buffer: std::borrow::Cow::Owned(lzw(&sub)),
        ..Default::default()
    }
}

/// GIF LZW compression of palette indices with a minimum code size of 8: the buffer of a
/// pre-encoded `gif::Frame` (the code size byte, then the codes packed from the low bit). The
/// dictionary is an open-addressing hash table of (prefix code, byte) pairs, emptied with a
/// clear code when its 4096 codes are used up.
pub(super) fn lzw(data: &[u8]) -> Vec<u8> {
    const MIN: u32 = 8;
    const CLEAR: u32 = 1 << MIN;
    const END: u32 = CLEAR + 1;
    const BITS: u32 = 13;
    const HSIZE: usize = 1 << BITS;
    let mut out = Vec::with_capacity(data.len() / 3 + 16);
    out.push(MIN as u8);
    let mut acc: u64 = 0;
    let mut nacc = 0u32;
    let mut emit = |out: &mut Vec<u8>, code: u32, size: u32| {
        acc |= (code as u64) << nacc;
        nacc += size;
        while nacc >= 8 {
            out.push(acc as u8);
            acc >>= 8;
            nacc -= 8;
        }
    };
    // Keys are (prefix << 8 | byte) + 1, 0 marking an empty slot.
    let mut keys = vec![0u32; HSIZE];
    let mut vals = vec![0u16; HSIZE];
    let mut size = MIN + 1;
    let mut next = END + 1;
    emit(&mut out, CLEAR, size);
    let Some((&first, rest)) = data.split_first() else {
        emit(&mut out, END, size);
        if nacc > 0 {
            out.push(acc as u8);
        }
        return out;
    };
    let mut prefix = first as u32;
    'bytes: for &b in rest {
        let key = ((prefix << 8) | b as u32) + 1;
        let mut h = (key.wrapping_mul(0x9E37_79B1) >> (32 - BITS)) as usize;
        loop {
            let k = keys[h];
            if k == key {
                prefix = vals[h] as u32;
                continue 'bytes;
            }
            if k == 0 {
                break;
            }
            h = (h + 1) & (HSIZE - 1);
        }
        emit(&mut out, prefix, size);
        let code = next;
        next += 1;
        keys[h] = key;
        vals[h] = code as u16;
        if code == 4095 {
            emit(&mut out, CLEAR, size);
            keys.fill(0);
            size = MIN + 1;
            next = END + 1;
        } else if code >= 1 << size {
            size += 1;
        }
        prefix = b as u32;
    }
    emit(&mut out, prefix, size);
    emit(&mut out, END, size);
    if nacc > 0 {
        out.push(acc as u8);
    }
    out
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

#[cfg(test)]
mod tests {
    use super::*;

    /// [`lzw`] output decodes, through the `gif` crate, to the indices it was given: runs,
    /// noise and enough data to fill and clear the dictionary many times.
    #[test]
    fn lzw_round_trips_through_the_gif_decoder() {
        let (w, h) = (300u16, 200u16);
        let mut data = Vec::with_capacity(w as usize * h as usize);
        let mut x = 12345u32;
        for i in 0..w as usize * h as usize {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
            data.push(match (i / 5000) % 3 {
                0 => (x >> 24) as u8,
                1 => (i / 700) as u8,
                _ => ((x >> 28) as u8) | 0xF0,
            });
        }
        let pal: Vec<u8> = (0..=255u8).flat_map(|v| [v, v, v]).collect();
        let mut bytes = Vec::new();
        {
            let mut enc = gif::Encoder::new(&mut bytes, w, h, &pal).unwrap();
            for d in [&data[..], &data[..1]] {
                let fr = gif::Frame {
                    width: if d.len() == data.len() {
                        w
                    } else {
                        d.len() as u16
                    },
                    height: if d.len() == data.len() { h } else { 1 },
                    buffer: std::borrow::Cow::Owned(lzw(d)),
                    ..Default::default()
                };
                enc.write_lzw_pre_encoded_frame(&fr).unwrap();
            }
        }
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::Indexed);
        let mut dec = opts.read_info(&bytes[..]).unwrap();
        let f = dec.read_next_frame().unwrap().unwrap();
        assert_eq!(&f.buffer[..], &data[..]);
        let f = dec.read_next_frame().unwrap().unwrap();
        assert_eq!(&f.buffer[..], &data[..1]);
        // No data: the code size, then the clear and end codes (9 bits each).
        assert_eq!(lzw(&[]), vec![8, 0x00, 0x03, 0x02]);
    }
}
