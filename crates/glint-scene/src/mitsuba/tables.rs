//! Mitsuba's named constants: indices of refraction of dielectrics (`int_ior="bk7"`)
//! and complex indices of refraction of conductors (`material="Au"`).

use glam::Vec3;

/// Mitsuba's dielectric table (values at about 589 nm, mostly from Hecht, *Optics*).
const IORS: [(&str, f32); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.000_036),
    ("hydrogen", 1.000_132),
    ("air", 1.000_277),
    ("carbon dioxide", 1.000_45),
    ("water", 1.333),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.520_45),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.47),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.575),
    ("diamond", 2.419),
];

/// The index of refraction Mitsuba gives `name` (case-insensitive).
pub(super) fn named_ior(name: &str) -> Option<f32> {
    let name = name.trim().to_ascii_lowercase();
    IORS.iter().find(|(n, _)| *n == name).map(|&(_, v)| v)
}

/// The names of [`named_ior`], for messages.
pub(super) fn ior_names() -> String {
    IORS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
}

/// RGB complex indices of refraction `(eta, k)` of the conductors Mitsuba names: the
/// measured spectra of Mitsuba's `data/ior` set integrated against the sRGB primaries,
/// as tabulated by Tungsten (`src/core/bsdfs/ComplexIorData.hpp`, B. Bitterli), with
/// the few slightly negative fitting artefacts clamped to zero.
const METALS: [(&str, Vec3, Vec3); 37] = [
    ("a-C", Vec3::new(2.9441, 2.2272, 1.9682), Vec3::new(0.8874, 0.7993, 0.8153)),
    ("Ag", Vec3::new(0.1553, 0.1167, 0.1384), Vec3::new(4.8283, 3.1222, 2.1470)),
    ("Al", Vec3::new(1.6575, 0.8804, 0.5212), Vec3::new(9.2239, 6.2695, 4.8370)),
    ("AlAs", Vec3::new(3.6051, 3.2329, 2.2176), Vec3::new(0.0007, 0.0000, 0.0074)),
    ("AlSb", Vec3::new(0.0000, 4.1428, 4.6698), Vec3::new(0.0000, 0.0938, 1.3007)),
    ("Au", Vec3::new(0.1431, 0.3750, 1.4425), Vec3::new(3.9832, 2.3857, 1.6032)),
    ("Be", Vec3::new(4.1851, 3.1851, 2.7841), Vec3::new(3.8354, 3.0101, 2.8690)),
    ("Cr", Vec3::new(4.3697, 2.9167, 1.6547), Vec3::new(5.2064, 4.2314, 3.7549)),
    ("CsI", Vec3::new(2.1449, 1.7023, 1.6624), Vec3::new(0.0000, 0.0000, 0.0000)),
    ("Cu", Vec3::new(0.2004, 0.9240, 1.1022), Vec3::new(3.9129, 2.4528, 2.1422)),
    ("Cu2O", Vec3::new(3.5493, 2.9521, 2.7369), Vec3::new(0.1132, 0.1947, 0.6002)),
    ("CuO", Vec3::new(3.2454, 2.4496, 2.1974), Vec3::new(0.5203, 0.5707, 0.7172)),
    ("d-C", Vec3::new(2.7113, 2.3186, 2.2289), Vec3::new(0.0000, 0.0000, 0.0000)),
    ("Hg", Vec3::new(2.3989, 1.4400, 0.9096), Vec3::new(6.3276, 4.3719, 3.4218)),
    ("HgTe", Vec3::new(4.7795, 3.2310, 2.6600), Vec3::new(1.6320, 1.5808, 1.7296)),
    ("Ir", Vec3::new(3.0864, 2.0822, 1.6179), Vec3::new(5.5922, 4.0672, 3.2673)),
    ("K", Vec3::new(0.0640, 0.0464, 0.0382), Vec3::new(2.1042, 1.3489, 0.9132)),
    ("Li", Vec3::new(0.2658, 0.1956, 0.2209), Vec3::new(3.5402, 2.3111, 1.6686)),
    ("MgO", Vec3::new(2.0896, 1.6507, 1.5949), Vec3::new(0.0000, 0.0000, 0.0000)),
    ("Mo", Vec3::new(4.4837, 3.5255, 2.7761), Vec3::new(4.1111, 3.4209, 3.1506)),
    ("Na_palik", Vec3::new(0.0603, 0.0561, 0.0620), Vec3::new(3.1793, 2.1125, 1.5791)),
    ("Nb", Vec3::new(3.4201, 2.7902, 2.3956), Vec3::new(3.4414, 2.7376, 2.5799)),
    ("Ni_palik", Vec3::new(2.3673, 1.6634, 1.4671), Vec3::new(4.4988, 3.0502, 2.3454)),
    ("Rh", Vec3::new(2.5858, 1.8602, 1.5544), Vec3::new(6.7823, 4.7030, 3.9761)),
    ("Se", Vec3::new(4.0593, 2.8427, 2.8208), Vec3::new(0.7544, 0.6385, 0.5216)),
    ("SiC", Vec3::new(3.1723, 2.5260, 2.4794), Vec3::new(0.0000, 0.0000, 0.0000)),
    ("SnTe", Vec3::new(4.5252, 1.9812, 1.2817), Vec3::new(0.0000, 0.0000, 0.0000)),
    ("Ta", Vec3::new(2.0626, 2.3931, 2.6281), Vec3::new(2.4080, 1.7414, 1.9470)),
    ("Te", Vec3::new(7.3908, 4.4821, 2.6371), Vec3::new(3.2561, 3.5274, 3.2922)),
    ("ThF4", Vec3::new(1.8307, 1.4422, 1.3876), Vec3::new(0.0000, 0.0000, 0.0000)),
    ("TiC", Vec3::new(3.7005, 2.8374, 2.5823), Vec3::new(3.2657, 2.3516, 2.1728)),
    ("TiN", Vec3::new(1.6485, 1.1504, 1.3798), Vec3::new(3.3685, 1.9435, 1.1020)),
    ("TiO2", Vec3::new(3.4566, 2.8017, 2.9051), Vec3::new(0.0001, 0.0000, 0.0006)),
    ("VC", Vec3::new(3.6576, 2.7527, 2.5327), Vec3::new(3.0684, 2.1987, 1.9632)),
    ("V_palik", Vec3::new(4.2775, 3.5132, 2.7611), Vec3::new(3.4912, 2.8894, 3.1117)),
    ("VN", Vec3::new(2.8656, 2.1192, 1.9401), Vec3::new(3.0323, 2.0561, 1.6163)),
    ("W", Vec3::new(4.3707, 3.3003, 2.9983), Vec3::new(3.5007, 2.6049, 2.2732)),
];

/// The RGB `(eta, k)` of Mitsuba's conductor `material` name; `none` is Mitsuba's
/// perfect mirror (eta 0, k 1, a Fresnel reflectance of 1 at every angle).
pub(crate) fn named_conductor(name: &str) -> Option<(Vec3, Vec3)> {
    if name == "none" {
        return Some((Vec3::ZERO, Vec3::ONE));
    }
    METALS.iter().find(|(n, _, _)| *n == name).map(|&(_, eta, k)| (eta, k))
}

/// The names of [`named_conductor`], for messages.
pub(super) fn conductor_names() -> String {
    let mut names: Vec<&str> = METALS.iter().map(|(n, _, _)| *n).collect();
    names.push("none");
    names.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_mitsuba_uses_are_in_the_tables() {
        assert_eq!(named_ior("bk7"), Some(1.5046));
        assert_eq!(named_ior("Air"), Some(1.000_277));
        assert_eq!(named_ior("polypropylene"), Some(1.49));
        assert!(named_conductor("Au").is_some_and(|(eta, k)| eta.x < eta.z && k.x > k.z));
        assert_eq!(named_conductor("none"), Some((Vec3::ZERO, Vec3::ONE)));
        assert_eq!(named_conductor("unobtainium"), None);
    }
}
