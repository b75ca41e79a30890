% The bar or column of the author_code_*.sh drivers (hompm's own Octave, not
% the author's): open uniform knots of degree `deg` on [0, constant.height]
% with `n_e` spans, `ppc` particles per span at the midpoints of equal
% sub-intervals (hompm's placement), and the time levels of `n_steps` steps.
% Expects constant, deg, n_e, ppc and n_steps; sets n_dof, Xi, h, pos_loc,
% pos, n_p, weight, nt and z for MPM_1D_B_spline.
n_dof = n_e + deg;
Xi = zeros(n_dof + deg + 1, 1);
mesh = 0:constant.height/(n_dof-deg):constant.height;
Xi(deg+2:n_dof+1, 1) = mesh(2:n_dof-deg+1);
Xi(end-deg:end, 1) = mesh(end);
h = constant.height / n_e;
loc = (1:2:(2*ppc-1)) / (2*ppc);
pos_loc = repmat(loc, 1, n_e);
pos = pos_loc(:) * h + kron(Xi(1+deg:end-deg-1), ones(ppc, 1));
n_p = n_e * ppc;
weight = h / ppc * ones(n_p, 1);
nt = n_steps + 1;
z = zeros(1, nt);
