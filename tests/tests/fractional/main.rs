//! Fractional (Grünwald–Letnikov, and its Caputo form) boundary value problems: the dense and fast solvers, orders, hard and ill-posed cases, bad input. One test binary for the group.

mod alpha_one;
mod caputo;
mod caputo_input;
mod corrected;
mod corrected_caputo;
mod end_forcing;
mod fractional_fast;
mod fractional_orders;
mod generic_data;
mod hard_fractional;
mod ill_posed_fractional;
mod indefinite;
mod infinite_action;
mod line_search;
