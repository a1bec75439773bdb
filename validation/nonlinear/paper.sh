# Sourced by summary.sh and ../run-all.sh: how this project's scheme names map onto the
# non-linear paper's table labels, and the paper's points read from validation/reference/.
# Needs $ref (the validation/reference directory) set by the caller.

# paper_case SCHEME: the paper's label of a run.sh scheme (empty if the paper has none).
paper_case() { case "$1" in ref) echo Ref;; cross) echo Cross;; dot_corrected) echo Dot;; twostep_dot) echo Two-step-dot;; *) echo "";; esac; }
# paper_dps SCHEME DENSITY: the paper's Delta p values of that scheme in Tables 3-7, in its order.
paper_dps() { awk -F, -v c="$(paper_case "$1")" -v n="$2" '$1 == c && $2 == n {print $3}' "$ref/nonlinear_tables3to7_nemd.csv"; }
