//! Closed-form theory (issue 4): placeholder until filled.
