//! Thin coloured glass: the paper's stained glass (§3.3) under two models.
//!
//! A pane has colour `c` and opacity `α ∈ [0, 1]`. Glass never stops a
//! ray; it tints it.
//! - [`GlassModel::Filter`] (physical, default): each crossing multiplies
//!   light by `t = (1 − α)·1 + α·c` per channel, so crossings commute.
//! - [`GlassModel::Blend`] (the paper's eq. 6): `b₁ = b₀(1 − α) + c·α`,
//!   applied in the order light meets the panes, starting from white.

use crate::color::Rgb;

/// A pane of thin coloured glass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Glass {
    /// The glass colour `c` (linear RGB, each channel in [0, 1]).
    pub color: Rgb,
    /// Opacity `α` in [0, 1]: 0 is clear, 1 passes only `c`.
    pub alpha: f32,
}

impl Glass {
    /// Per-channel transmittance of one crossing under the filter model:
    /// `t = (1 − α) + α·c`.
    #[inline]
    pub fn filter_transmittance(&self) -> Rgb {
        Rgb::splat(1.0 - self.alpha) + self.alpha * self.color
    }

    /// The paper's eq. 6: the blend value after light of blend `b0`
    /// crosses this pane, `b₁ = b₀(1 − α) + c·α`.
    #[inline]
    pub fn blend(&self, b0: Rgb) -> Rgb {
        b0 * (1.0 - self.alpha) + self.color * self.alpha
    }
}

/// How successive glass crossings combine, chosen per scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GlassModel {
    /// Multiply per-crossing transmittances (commutative).
    #[default]
    Filter,
    /// The paper's eq. 6, in crossing order from the light.
    Blend,
}

impl GlassModel {
    /// The tint of light that crosses `panes`, listed in the order the
    /// light meets them (from the light towards the lit point).
    pub fn tint<'a>(self, panes: impl IntoIterator<Item = &'a Glass>) -> Rgb {
        panes
            .into_iter()
            .fold(Rgb::ONE, |t, g| self.tint_after(t, g))
    }

    /// The tint of light of tint `before` after it crosses `pane`.
    #[inline]
    pub fn tint_after(self, before: Rgb, pane: &Glass) -> Rgb {
        match self {
            GlassModel::Filter => before * pane.filter_transmittance(),
            GlassModel::Blend => pane.blend(before),
        }
    }
}
