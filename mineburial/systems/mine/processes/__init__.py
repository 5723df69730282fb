"""The mine's post-impact processes: the seam and registry (:mod:`.registry`) and scour, the first
process (docs/design.md, "Post-impact processes")."""
