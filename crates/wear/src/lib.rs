//! Archard wear on body-fixed pin and bearing grids.
//!
//! This crate will hold worn surfaces as data (body-fixed grids of worn radii with a smooth
//! periodic interpolation that implements the `contact` crate's surface profile), Archard wear
//! accumulation over accepted integration steps, and staged wear extrapolation.
