//! Coordinate conversions and motion descriptions for the console's text.

use crate::console::jog::JogMotion;

/// Polar [delta, azimuth, radius] (0.1°, 0.1°, 0.1 mm) to cartesian 0.1 mm about the base origin.
pub fn cartesian_of(polar: [i32; 3]) -> [i32; 3] {
    let el = (f64::from(polar[0]) / 10.0).to_radians();
    let az = (f64::from(polar[1]) / 10.0).to_radians();
    let r = f64::from(polar[2]);
    [
        r * el.cos() * az.cos(),
        r * el.cos() * az.sin(),
        r * el.sin(),
    ]
    .map(|v| v.round() as i32)
}

/// Cartesian tenths of mm to polar [delta, azimuth, radius] in tenths.
pub fn polar_of(c: [i32; 3]) -> [i32; 3] {
    let [x, y, z] = c.map(f64::from);
    let horizontal = x.hypot(y);
    [
        (z.atan2(horizontal).to_degrees() * 10.0).round() as i32,
        (y.atan2(x).to_degrees() * 10.0).round() as i32,
        (x.hypot(y).hypot(z)).round() as i32,
    ]
}

/// Motion a jog would command, for the status bar.
pub fn describe_motion(motion: JogMotion) -> String {
    let sign = |v: i8| match v {
        1 => "+",
        -1 => "-",
        _ => "",
    };
    // The axes that move, the sign before a cartesian or turn axis ("+X") and after a pan's ("az+").
    let moving = |axes: &[(&str, i8)], sign_first: bool| {
        let parts = axes
            .iter()
            .filter(|(_, v)| *v != 0)
            .map(|(axis, v)| match sign_first {
                true => format!("{}{axis}", sign(*v)),
                false => format!("{axis}{}", sign(*v)),
            });
        parts.collect::<Vec<_>>().join(" ")
    };
    match motion {
        JogMotion::Cartesian { x, y, z } => moving(&[("X", x), ("Y", y), ("Z", z)], true),
        JogMotion::Polar { azimuth, altitude } => {
            moving(&[("az", azimuth), ("alt", altitude)], false)
        }
        JogMotion::Joint { joint, direction } => format!("J{joint}{}", sign(direction)),
        JogMotion::Orientation { rx, ry, rz } => {
            moving(&[("Rx", rx), ("Ry", ry), ("Rz", rz)], true)
        }
    }
}
