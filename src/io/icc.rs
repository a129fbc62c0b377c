//! ICC colour profiles: checking a photo's embedded profile, and the sRGB
//! profile grime embeds in layered and 16-bit outputs of photos that have
//! none (without one, Krita opens a 16-bit PNG or PSD as linear light).

/// Largest embedded profile grime accepts (real profiles are 0.5-600 kB;
/// a few camera and printer profiles reach 1-2 MB).
pub const MAX_ICC_BYTES: usize = 4 << 20;

/// Checks an embedded ICC profile: at most [`MAX_ICC_BYTES`], a header whose
/// size field matches the data (ICC.1:2010 sec. 7.2.2) and the `acsp`
/// signature at byte 36 (sec. 7.2.9).
///
/// # Errors
/// A short reason, e.g. `is 1.0 GiB, over the 4 MiB grime accepts`.
pub fn check(profile: &[u8]) -> Result<(), String> {
    if profile.len() > MAX_ICC_BYTES {
        return Err(format!(
            "is {}, over the {} grime accepts",
            super::human_bytes(profile.len() as u64),
            super::human_bytes(MAX_ICC_BYTES as u64)
        ));
    }
    if profile.len() < 132 {
        return Err(format!(
            "is {} bytes, too short to be a profile",
            profile.len()
        ));
    }
    let size = u32::from_be_bytes([profile[0], profile[1], profile[2], profile[3]]) as usize;
    if size != profile.len() {
        return Err(format!(
            "is damaged: its header gives {size} bytes but it has {}",
            profile.len()
        ));
    }
    if &profile[36..40] != b"acsp" {
        return Err("is damaged: no 'acsp' signature in its header".into());
    }
    Ok(())
}

/// The sRGB colour space (IEC 61966-2-1) as an ICC v2 display profile:
/// D50-adapted primaries (Bradford), D50 white and the sRGB tone curve
/// sampled at 1024 points, shared by the three channels. About 2.5 kB,
/// built the same way every time.
pub fn srgb() -> &'static [u8] {
    static PROFILE: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    PROFILE.get_or_init(build_srgb)
}

fn s15(v: f64) -> [u8; 4] {
    ((v * 65536.0).round() as i32).to_be_bytes()
}

fn xyz(v: [f64; 3]) -> Vec<u8> {
    let mut t = b"XYZ \0\0\0\0".to_vec();
    for c in v {
        t.extend_from_slice(&s15(c));
    }
    t
}

fn build_srgb() -> Vec<u8> {
    const D50: [f64; 3] = [0.9642, 1.0, 0.8249];
    let desc = {
        let text = b"sRGB IEC61966-2.1\0";
        let mut t = b"desc\0\0\0\0".to_vec();
        t.extend_from_slice(&(text.len() as u32).to_be_bytes());
        t.extend_from_slice(text);
        // No Unicode or ScriptCode description: codes and counts 0, then
        // the 67-byte ScriptCode field.
        t.extend_from_slice(&[0; 4 + 4 + 2 + 1 + 67]);
        t
    };
    let cprt = {
        let mut t = b"text\0\0\0\0".to_vec();
        t.extend_from_slice(b"No copyright, use freely\0");
        t
    };
    let curve = {
        const N: usize = 1024;
        let mut t = b"curv\0\0\0\0".to_vec();
        t.extend_from_slice(&(N as u32).to_be_bytes());
        for i in 0..N {
            let v = i as f64 / (N - 1) as f64;
            // IEC 61966-2-1 decoding function.
            let lin = if v <= 0.04045 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            };
            t.extend_from_slice(&((lin * 65535.0).round() as u16).to_be_bytes());
        }
        t
    };
    let tags: [(&[u8; 4], Vec<u8>); 6] = [
        (b"desc", desc),
        (b"cprt", cprt),
        (b"wtpt", xyz(D50)),
        (b"rXYZ", xyz([0.4360747, 0.2225045, 0.0139322])),
        (b"gXYZ", xyz([0.3850649, 0.7168786, 0.0971045])),
        (b"bXYZ", xyz([0.1430804, 0.0606169, 0.7141733])),
    ];
    // Three TRC entries point at the one curve.
    let entries = tags.len() + 3;
    let mut data = Vec::new();
    let mut table = Vec::new();
    let mut offset = 128 + 4 + 12 * entries;
    let mut put = |sig: &[u8; 4], at: usize, len: usize| {
        table.extend_from_slice(sig);
        table.extend_from_slice(&(at as u32).to_be_bytes());
        table.extend_from_slice(&(len as u32).to_be_bytes());
    };
    for (sig, body) in &tags {
        put(sig, offset, body.len());
        data.extend_from_slice(body);
        while !data.len().is_multiple_of(4) {
            data.push(0);
        }
        offset = 128 + 4 + 12 * entries + data.len();
    }
    for sig in [b"rTRC", b"gTRC", b"bTRC"] {
        put(sig, offset, curve.len());
    }
    data.extend_from_slice(&curve);

    let size = 128 + 4 + table.len() + data.len();
    let mut p = Vec::with_capacity(size);
    p.extend_from_slice(&(size as u32).to_be_bytes());
    p.extend_from_slice(&[0; 4]); // preferred CMM
    p.extend_from_slice(&[2, 0x10, 0, 0]); // version 2.1
    p.extend_from_slice(b"mntrRGB XYZ ");
    // Creation date 2000-01-01 00:00:00, fixed so the bytes never change.
    for v in [2000u16, 1, 1, 0, 0, 0] {
        p.extend_from_slice(&v.to_be_bytes());
    }
    p.extend_from_slice(b"acsp");
    p.extend_from_slice(&[0; 24]); // platform, flags, maker, model, attributes
    p.extend_from_slice(&[0; 4]); // perceptual intent
    for c in D50 {
        p.extend_from_slice(&s15(c));
    }
    p.resize(128, 0); // creator, ID, reserved
    p.extend_from_slice(&(entries as u32).to_be_bytes());
    p.extend_from_slice(&table);
    p.extend_from_slice(&data);
    debug_assert_eq!(p.len(), size);
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_profile_is_well_formed() {
        let p = srgb();
        assert_eq!(check(p), Ok(()));
        assert!(p.len() < 3000, "{}", p.len());
        // Tag table: every tag lies inside the profile.
        let n = u32::from_be_bytes(p[128..132].try_into().unwrap()) as usize;
        assert_eq!(n, 9);
        for i in 0..n {
            let e = &p[132 + 12 * i..144 + 12 * i];
            let at = u32::from_be_bytes(e[4..8].try_into().unwrap()) as usize;
            let len = u32::from_be_bytes(e[8..12].try_into().unwrap()) as usize;
            assert!(at.is_multiple_of(4) && at + len <= p.len(), "tag {i}");
        }
    }

    #[test]
    fn garbage_and_huge_profiles_are_refused() {
        assert!(check(b"garbage").is_err());
        let mut p = srgb().to_vec();
        p[36] = b'x';
        assert!(check(&p).unwrap_err().contains("acsp"));
        let mut p = srgb().to_vec();
        p.push(0);
        assert!(check(&p).unwrap_err().contains("header"));
        let mut big = vec![0u8; MAX_ICC_BYTES + 1];
        let len = big.len() as u32;
        big[..4].copy_from_slice(&len.to_be_bytes());
        big[36..40].copy_from_slice(b"acsp");
        assert!(check(&big).unwrap_err().contains("over"));
    }
}
