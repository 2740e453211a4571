//! Stroke ordering by depth (thesis §5.2).
