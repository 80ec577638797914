//! Lanes of f64 for the soft step's bundles: `Wide`, W values with lane-wise arithmetic written so that the
//! compiler turns it into vector instructions, each lane's result exactly the scalar operation's (no fused
//! multiply-add), and the few vector helpers the bundles use.

/// Rows in a bundle.
pub(crate) const W: usize = 8;

/// One value per lane.
pub(crate) type Lanes = [f64; W];

/// A vector per lane, by component.
pub(crate) type Vec3Lanes = [Lanes; 3];

/// W f64 lanes with lane-wise arithmetic, which the compiler turns into vector instructions (each lane's result is
/// exactly the scalar operation's: no fused multiply-add).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Wide(pub(crate) [f64; W]);

macro_rules! lanewise {
    ($trait:ident, $fn:ident, $op:tt) => {
        impl std::ops::$trait for Wide {
            type Output = Wide;
            #[inline(always)]
            fn $fn(self, o: Wide) -> Wide {
                let (a, b) = (self.0, o.0);
                Wide(std::array::from_fn(|l| a[l] $op b[l]))
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Wide {
    #[inline(always)]
    pub(crate) fn splat(x: f64) -> Wide {
        Wide([x; W])
    }
    #[inline(always)]
    pub(crate) fn neg(self) -> Wide {
        let a = self.0;
        Wide(std::array::from_fn(|l| -a[l]))
    }
    #[inline(always)]
    pub(crate) fn max(self, o: Wide) -> Wide {
        let (a, b) = (self.0, o.0);
        Wide(std::array::from_fn(|l| a[l].max(b[l])))
    }
    #[inline(always)]
    pub(crate) fn min(self, o: Wide) -> Wide {
        let (a, b) = (self.0, o.0);
        Wide(std::array::from_fn(|l| a[l].min(b[l])))
    }
    #[inline(always)]
    pub(crate) fn abs(self) -> Wide {
        let a = self.0;
        Wide(std::array::from_fn(|l| a[l].abs()))
    }
    #[inline(always)]
    pub(crate) fn sqrt(self) -> Wide {
        let a = self.0;
        Wide(std::array::from_fn(|l| a[l].sqrt()))
    }
    /// Lanes where self > o.
    #[inline(always)]
    pub(crate) fn gt(self, o: Wide) -> [bool; W] {
        let (a, b) = (self.0, o.0);
        std::array::from_fn(|l| a[l] > b[l])
    }
    /// `yes` where `m`, else `no`.
    #[inline(always)]
    pub(crate) fn select(m: [bool; W], yes: Wide, no: Wide) -> Wide {
        let (a, b) = (yes.0, no.0);
        Wide(std::array::from_fn(|l| if m[l] { a[l] } else { b[l] }))
    }
}

/// Lanes of a vector's components.
#[inline(always)]
pub(crate) fn wide3(v: &Vec3Lanes) -> [Wide; 3] {
    [Wide(v[0]), Wide(v[1]), Wide(v[2])]
}

/// The dot product lane by lane ((x0 y0 + x1 y1) + x2 y2, as nalgebra sums).
#[inline(always)]
pub(crate) fn dot(x: &[Wide; 3], y: &[Wide; 3]) -> Wide {
    x[0] * y[0] + x[1] * y[1] + x[2] * y[2]
}
