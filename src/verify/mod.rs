//! Checks of a finished run made from its outputs alone, apart from the code that made them:
//! how deep any two bodies' solids overlap at the output rows' poses, by parry's GJK/EPA and
//! not by the contact code ([`overlap`]; `foldsim overlaps`, docs/contact.md §3).

pub mod overlap;
