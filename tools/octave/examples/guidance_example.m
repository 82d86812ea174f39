% guidance_example.m -- the paper's compliant straight guidance (Boer et al. 2013, Section 4.1) run
% from Octave with flexmb's spacar(), and the response plotted: the horizontal motion of the body
% (node 6) under the load pulse of Eq. 24, the bending stress at the clamp and the clamp reaction.
% Run from anywhere after addpath('<flexmb>/build/octave'); writes its files to a temporary folder.
here = fileparts(mfilename('fullpath'));
model = fullfile(here, '..', '..', '..', 'datfiles', 'straight_guidance.dat');
work = tempname();
mkdir(work);
copyfile(model, fullfile(work, 'straight_guidance.dat'));
old = cd(work);
spacar(1, 'straight_guidance');           % time, x, e, sig, lnp, le, ... in the workspace
cd(old);
u = x(:, lnp(6, 1)) - x(1, lnp(6, 1));    % horizontal displacement of node 6
M = sig(:, le(1, 2));                     % generalised bending stress of element 1 at the clamp (docs/theory/dat-format.md)
F = fxt(:, lnp(1, 1));                    % horizontal clamp force (reaction, node 1)
printf('max |u6| = %.4f mm at t = %.3f s; max |sig2| of element 1 = %.4f; files in %s\n', 1000 * max(abs(u)), ...
       time(find(abs(u) == max(abs(u)), 1)), max(abs(M)), work);
if exist('OCTAVE_VERSION', 'builtin') && (isempty(available_graphics_toolkits()) || isempty(getenv('DISPLAY')))
  disp('no display: plot skipped');
  return;
end
subplot(2, 1, 1);
plot(time, 1000 * u);
xlabel('time [s]'); ylabel('u_6 [mm]'); title('Straight guidance: body motion (flexmb via spacar)');
subplot(2, 1, 2);
plot(time, M, time, F);
xlabel('time [s]'); legend('sig(:, le(1, 2)): bending stress at clamp 1', 'horizontal reaction at node 1 [N]');
