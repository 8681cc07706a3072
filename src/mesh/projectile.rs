//! Projectile meshers (in progress).
