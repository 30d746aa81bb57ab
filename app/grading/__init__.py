"""Grading: the controller battery (probes, trials, robustness, the SP-law checks), the services
exercises over HTTP, the wall trials of the mobile lab, the similarity report: what `hri-lab grade`,
`grade-services`, `grade-wall` and the Gradescope autograder run (docs/design.md, Layout)."""
