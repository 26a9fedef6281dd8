//! The arm near a singularity, for the status bar. Neither link reports it: an estimate, the
//! condition number of the Gen3 model's Jacobian ([`crate::kortex::gen3::condition_number`]) at the
//! reported angles; none without telemetry.

use crate::kortex::Telemetry;
use crate::kortex::gen3::condition_number;

pub use crate::kortex::gen3::SINGULARITY_WARNING;

/// From here (about 0.08° short of a straight elbow) the text says at, not near.
pub const AT_SINGULARITY: f64 = 10_000.0;

/// The condition number above [`SINGULARITY_WARNING`]; `None` below or without an estimate.
pub fn near_singularity(t: &Telemetry) -> Option<f64> {
    let q_deg = t.joints.map(|j| f64::from(j.position));
    if !q_deg.iter().all(|a| a.is_finite()) {
        return None;
    }
    let kappa = condition_number(&q_deg.map(f64::to_radians));
    (kappa > SINGULARITY_WARNING).then_some(kappa)
}

/// `near singularity (κ 76)`, or `at singularity` from [`AT_SINGULARITY`] on.
pub fn singularity_text(kappa: f64) -> String {
    if kappa < AT_SINGULARITY {
        format!("near singularity (κ {kappa:.0})")
    } else {
        "at singularity".to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kortex::RegisterImage;
    use crate::kortex::gen3::HOME_DEG;

    fn reporting(q_deg: [f64; 7]) -> Telemetry {
        let mut t = Telemetry::decode(&RegisterImage::default());
        for (joint, q) in t.joints.iter_mut().zip(q_deg) {
            // As the arm reports them: 0 to 360.
            joint.position = q.rem_euclid(360.0) as f32;
        }
        t
    }

    #[test]
    fn home_is_not_near_and_a_nearly_straight_elbow_is() {
        assert_eq!(near_singularity(&reporting(HOME_DEG)), None);
        let mut q = HOME_DEG;
        q[3] = -11.0;
        assert_eq!(near_singularity(&reporting(q)), None);
        q[3] = -5.0;
        let kappa = near_singularity(&reporting(q)).expect("5 deg short of straight");
        assert!((kappa - 152.0).abs() < 1.0, "{kappa}");
        assert_eq!(singularity_text(kappa), "near singularity (κ 152)");
        q[3] = 0.0;
        let kappa = near_singularity(&reporting(q)).expect("straight");
        assert_eq!(singularity_text(kappa), "at singularity");
    }

    #[test]
    fn an_angle_that_is_not_a_number_gives_no_estimate() {
        let mut t = reporting(HOME_DEG);
        t.joints[3].position = f32::NAN;
        assert_eq!(near_singularity(&t), None);
    }
}
