"""Benchmark: every design of ``designs/`` built the way ``glidectl report`` builds it, cold and warm.

Per design, in a fresh Python process each (no state shared between designs):

- **cold**: the build with an empty cache (``build_designs(..., jobs=1)`` into a new output folder), wall time;
- **warm**: the same build again with nothing changed (a cache hit: the files are rewritten from ``OUT/.cache``);
- **profile** (``--profile``): one more cold build under ``cProfile``, its wall time (with the profiler's overhead)
  and the top 10 functions by cumulative time.

Then, unless ``--no-total``, ``glidectl report all`` itself as a user runs it (a subprocess, ``--jobs`` default):
cold (``--no-cache``) and warm, total wall time including the interpreter start.

Run from the project root::

    python bench/bench_report_all.py                       # quick settings, every design
    python bench/bench_report_all.py --full                # the reports' full settings
    python bench/bench_report_all.py --designs ch6_controllers,ch7_ctol --profile --no-total
    python bench/bench_report_all.py --full --no-total --baseline-src ../base/src   # before/after, same run

Writes ``bench/results/report_all.json`` (``--tag`` adds a suffix: ``report_all_<tag>.json``).

Measured 2026-12-02 (eighth session, a 2-core machine about 1.7 times slower than the one of the earlier notes), the
README's main job cold, ``OMP_NUM_THREADS=1 PYTHONPATH=src /usr/bin/time -v python -m glidectl report all --no-cache
--jobs 2 --out DIR`` in a checkout of each version, one after the other on the idle machine ("done in" per design,
measured in its worker beside the others):

=====================  ==========  ==========
design                 b8bdaf6     cca7e35
=====================  ==========  ==========
ch2_longitudinal       31.4 s      20.7 s
ch4_phugoid            12.8 s      10.2 s
ch5_singular_pert.     28.9 s      30.5 s
ch6_controllers        63.9 s      57.6 s
ch7_ctol               200.8 s     181.1 s
ch8_helix              106.8 s     106.4 s
roa_certification      1053.8 s    868.8 s
slocum_dive_cycle      265.0 s     293.2 s
end to end (wall)      1063.1 s    875.2 s  (ratio 0.82)
user CPU               1920.4 s    1651.9 s (0.86)
peak RSS               2.60 GB     0.82 GB
=====================  ==========  ==========

The warm rebuild (nothing changed, every design a cache hit) took 4.8 s. The makespan is about the CPU time over
the 2 cores, so only less CPU shortens it. Within roa_certification the CTOL certificate took 265.9 s against 535.7
s, and the saturated user glider's SOS path is now the longest part (478.6 s in the build).

Measured 2026-12-03 (ninth session, a machine about 1.6 times faster; its speed drifts by up to 30 % between runs,
so the pair below ran side by side, both builds at once with ``--jobs 2``, 4 processes on 2 cores), abe1ee5 against
a1b820c (the moment route's row-grouped Schur complement):

=====================  ==========  ==========
design                 abe1ee5     a1b820c
=====================  ==========  ==========
ch2_longitudinal       28.8 s      29.0 s
ch4_phugoid            13.8 s      13.4 s
ch5_singular_pert.     33.0 s      33.2 s
ch6_controllers        62.1 s      66.0 s
ch7_ctol               266.2 s     265.9 s
ch8_helix              153.9 s     151.5 s
slocum_dive_cycle      356.1 s     357.4 s
roa_certification      1083.8 s    1054.3 s
end to end (wall)      1092.2 s    1063.5 s (ratio 0.97)
user CPU               1018.2 s    1000.9 s (0.98)
=====================  ==========  ==========

Every ledger number other than timings agreed to 1e-9 relative. Alone on the idle machine, abe1ee5 took 523.8 s
(CPU 923 s) at 05:17 and main (636c432) 533.7 s (CPU 1005 s) at 07:17, when the untouched ch7 was 24 % slower;
the warm rebuild took 3.1 s.

Measured 2026-12-03 08:32-08:53 (tenth session, the same machine, slower that hour: the builds took 10 % longer
than the ninth session's pair), side by side in the same way, 4582c9b against fbd808e (the first remainder-box
round sampled only when kept, the final margin check polished):

=====================  ==========  ==========
design                 4582c9b     fbd808e
=====================  ==========  ==========
ch2_longitudinal       32.7 s      33.2 s
ch4_phugoid            14.9 s      14.3 s
ch5_singular_pert.     36.7 s      39.0 s
ch6_controllers        83.7 s      78.1 s
ch7_ctol               323.5 s     314.6 s
ch8_helix              178.2 s     176.0 s
slocum_dive_cycle      432.9 s     430.3 s
roa_certification      1198.0 s    1180.5 s
end to end (wall)      1207.5 s    1190.8 s (ratio 0.99)
user CPU               1151.7 s    1128.8 s (0.98)
peak RSS               0.80 GB     0.80 GB
=====================  ==========  ==========

Numbers that changed (``cmpnum.py``-style comparison of every ``numbers.json``, 1e-9 relative): only the CTOL
certificate's, which now passes its final margin check at backoff 0.003 instead of 0.009:
``ctol_certified_volume`` 0.0021240 -> 0.0021606, ``ctol_ratio_to_theorem5`` 421893 -> 429167,
``ctol_fraction_of_true`` 0.001770 -> 0.001801. Inside the build, the CTOL part took 425.8 s against 482.2 s.

Measured 2026-12-03 13:02-13:21 (eleventh session, the same machine), side by side in the same way, 34741c0 against
b6358e3 (the alternation judges thin sets by the directed volume estimate; iterations per degree, which no design
uses; the certificate's times). The designs it does not touch differ by the load alone (ch2 16.3 s against 36.1 s):

=====================  ==========  ==========
design                 34741c0     b6358e3
=====================  ==========  ==========
ch2_longitudinal       36.1 s      16.3 s
ch4_phugoid            15.0 s      8.4 s
ch5_singular_pert.     34.8 s      23.9 s
ch6_controllers        91.5 s      78.1 s
ch7_ctol               289.9 s     285.7 s
ch8_helix              158.9 s     151.3 s
slocum_dive_cycle      373.4 s     492.7 s
roa_certification      1096.0 s    1121.5 s
end to end (wall)      1104.7 s    1130.9 s (ratio 1.02)
user CPU               1034.7 s    1085.3 s (1.05)
peak RSS               0.80 GB     0.80 GB
=====================  ==========  ==========

Numbers that changed (every ``numbers.json``, 1e-9 *relative*; an absolute tolerance misses changes to volumes of
1e-11): the user glider's unsaturated LQR loop, whose sets held no Sobol point, so that no V step had counted:
``roa_lqr_volume`` (slocum_dive_cycle) 1.553e-12 -> 3.633e-11 and ``sat_user_unsat_sos_volume_ratio`` 854.3 ->
19980.9; the saturated loop's first round now keeps its 4th V step, which changes the second round's box:
``sat_user_sat_sos_volume_ratio`` 2059.1 -> 1922.2. The price is the extra V steps' path on those two loops: the
slocum design +119 s and the unsaturated part of roa_certification +84 s in these loaded builds (the Slocum ROA
alone: 82 s against 61 s). A build of 29223a0 (the directed step volume; the same numbers as b6358e3) alone at
11:46: **490.4 s** end to end, CPU 916.1 s.

Measured 2026-12-03 14:19-14:40 (twelfth session, the same machine), side by side in the same way, 40abd49 against
96cf89b (``cached`` values shared by the designs of one build: the user glider's LQR-loop certificate, which
slocum_dive_cycle and roa_certification both made, is computed once; roa_certification's SOS path on it now runs
certify_roa's default checks, 20000 samples and 256 simulations, as slocum_dive_cycle's):

=====================  ==========  ==========
design                 40abd49     96cf89b
=====================  ==========  ==========
ch2_longitudinal       32.1 s      31.2 s
ch4_phugoid            12.7 s      13.5 s
ch5_singular_pert.     31.6 s      32.5 s
ch6_controllers        80.2 s      85.0 s
ch7_ctol               309.1 s     307.6 s
ch8_helix              174.8 s     174.9 s
slocum_dive_cycle      502.6 s     502.3 s (computed the shared certificate: 0/1 sub-results from the cache)
roa_certification      1204.9 s    1176.2 s (read it: 1/1; its part waited 127 s for slocum_dive_cycle's lock)
end to end (wall)      1210.5 s    1182.1 s (ratio 0.98)
user CPU               1149.3 s    1081.1 s (0.94)
peak RSS               0.80 GB     0.80 GB
=====================  ==========  ==========

No ledger number changed (every ``numbers.json``, 1e-9 relative, timings left out). The unsaturated user loop's
verification note in roa_certification now reads 10007 samples and 256/256 simulations (it read 2000 and 32/32).
The wall time gains less than the CPU: in that build slocum_dive_cycle started its certificate at 310 s (after
ch7_ctol), after roa_certification's part had asked for it, so the part waited. The part now runs last in
roa_certification (after that measurement), by when a full build has the certificate.

Measured 2026-12-03 15:27-15:47, side by side in the same way, 40abd49 against ec160bc (the above, the shared part
last, slocum_dive_cycle's FULL certificate without a time limit, as roa_certification's: the same cache key, and the
first remainder-box round's sampled checks skipped when the second replaces it; the moment route's Schur complement
without its 63 MB copies, bitwise the same):

=====================  ==========  ==========
design                 40abd49     ec160bc
=====================  ==========  ==========
ch2_longitudinal       30.6 s      30.1 s
ch4_phugoid            10.5 s      12.7 s
ch5_singular_pert.     31.0 s      30.4 s
ch6_controllers        83.7 s      85.8 s
ch7_ctol               307.8 s     306.9 s
ch8_helix              161.7 s     170.0 s
slocum_dive_cycle      480.6 s     468.1 s (computed the shared certificate: 0/1 sub-results from the cache)
roa_certification      1158.3 s    1116.4 s (read it: 1/1; the part took 34.9 s against 268.3 s, no wait)
end to end (wall)      1166.0 s    1124.7 s (ratio 0.96)
user CPU               1137.1 s    1065.3 s (0.94)
peak RSS               0.80 GB     0.80 GB
=====================  ==========  ==========

No ledger number changed (1e-9 relative, timings left out). The CTOL certificate inside roa_certification took
369.5 s against 407.4 s in this loaded pair. 04e49a9 (the same numbers) built alone at 15:54, nothing else running:
**480.3 s** for the 8 designs (8 min 3 s with the interpreter), CPU 908.0 s, peak 0.80 GB; roa_certification,
the critical path, 477.5 s. The warm rebuild after it: 4.7 s, 8 of 8 from the cache.

Measured 2026-12-03 16:39-17:01, the README's command as a user runs it (no thread variables set:
``PYTHONPATH=src /usr/bin/time -v python -m glidectl report all --no-cache --jobs 2 --out DIR``), side by side,
68af791 against 9af701c (the build's workers get ``cores // jobs`` library threads, ``glidectl.report.threads``):

=====================  ==========  ==========
design                 68af791     9af701c
=====================  ==========  ==========
ch2_longitudinal       17.8 s      27.5 s
ch4_phugoid            5.4 s       9.8 s
ch5_singular_pert.     15.9 s      34.0 s
ch6_controllers        59.3 s      111.0 s
ch7_ctol               281.9 s     281.2 s
ch8_helix              181.4 s     172.7 s
slocum_dive_cycle      649.6 s     527.4 s (its certificate step: 424.7 s against 312.0 s)
roa_certification      1290.9 s    1155.5 s
end to end (wall)      1296.2 s    1171.8 s (ratio 0.90)
user CPU               1547.5 s    948.1 s (0.61)
share of the 2 cores   121 %       82 %
peak RSS               0.81 GB     0.80 GB
=====================  ==========  ==========

With the libraries' defaults every worker ran one OpenBLAS and one rayon (Clarabel's faer) thread per core, and the
idle ones spin: 68af791 burnt 1.6 times the CPU for the same work and took 121 % of the machine against 82 %, which
is why the short designs of 9af701c, built while 68af791's spinning threads held the cores, took longer in this
pair. Numbers that changed: the certificates' volumes, by the rounding of the linear algebra, which depends on the
number of threads (a parallel BLAS or factorization adds in another order, and the SOS alternation carries that
difference along its path): roa_certification's full_KM100 volume +1.8e-5 relative, the reduced glider's area
-7.9e-5, the saturated user loop's SOS volume 3.662e-12 against 3.389e-12 (-7.4 %), the unsaturated one's +0.2 %,
slocum_dive_cycle's LQR-loop certificate +0.17 %; every certificate stays certified, no ledger flag changed. The new
numbers are those of a single-threaded run (the saturated user loop alone, one thread: 3.389e-12, the same).

Then each alone, the same command (``--jobs`` default: 2), nothing else running: 68af791 at 17:23-17:36 against
9af701c at 17:10-17:19:

=====================  ==========  ==========
design                 68af791     9af701c
=====================  ==========  ==========
ch2_longitudinal       19.8 s      9.6 s
ch4_phugoid            6.5 s       4.3 s
ch5_singular_pert.     17.0 s      10.3 s
ch6_controllers        34.9 s      28.3 s
ch7_ctol               190.5 s     150.1 s
ch8_helix              90.2 s      67.8 s
slocum_dive_cycle      343.7 s     251.1 s (computed the shared certificate)
roa_certification      753.6 s     504.6 s (read it: 1/1)
end to end (wall)      756.9 s     **517.5 s (ratio 0.68)**, 8 min 42 s with the interpreter
user CPU               1457.9 s    1006.3 s (0.69)
=====================  ==========  ==========

The warm rebuild after it: 3.9 s, 8 of 8 from the cache. 9af701c's numbers were the same alone as in the pair
(1e-9 relative): with one thread per worker the build is deterministic. 04e49a9's 480.3 s above was measured with
``OMP_NUM_THREADS=1`` set by hand (rayon still at one thread per core), an hour earlier on this machine that drifts
by +-30 %; the README's command, as a user runs it, took 756.9 s before this change.

Measured 2026-12-03 19:07-20:49 (sixth session), the README's command (no thread variables set), 665699d against
2274156 (the CTOL single-state float path, full_rhs_nondimensional evaluating the glider once): side by side
(``--jobs 2`` each, 4 processes on 2 cores), then alone twice, in both orders (new, base; base, new):

=====================  ==========  ==========  ==========  ==========  ==========  ==========
design                 pair 665..  pair 227..  alone1 665  alone1 227  alone2 665  alone2 227
=====================  ==========  ==========  ==========  ==========  ==========  ==========
ch2_longitudinal       16.2 s      20.0 s      9.5 s       10.3 s      10.3 s      7.6 s
ch4_phugoid            4.6 s       8.7 s       3.8 s       3.9 s       3.8 s       3.1 s
ch5_singular_pert.     21.5 s      20.3 s      9.8 s       13.4 s      13.9 s      9.3 s
ch6_controllers        59.7 s      65.7 s      32.0 s      32.4 s      40.2 s      28.9 s
ch7_ctol               322.0 s     296.2 s     151.0 s     103.2 s     146.2 s     140.9 s
ch8_helix              137.2 s     142.4 s     88.3 s      68.4 s      79.9 s      68.2 s
slocum_dive_cycle      433.8 s     439.3 s     231.2 s     186.0 s     210.8 s     237.1 s
roa_certification      990.6 s     974.0 s     500.9 s     410.5 s     496.3 s     481.9 s
end to end (wall)      1000.2 s    990.6 s     517.3 s     417.2 s     504.9 s     492.9 s
user CPU               938.0 s     912.7 s     1004.9 s    813.6 s     981.8 s     958.2 s
=====================  ==========  ==========  ==========  ==========  ==========  ==========

The gain is about 2-3 % of the CPU (pair 0.97, second alone pair 0.98); the first alone pair's 0.81 is the machine's
drift (ch8_helix, whose code did not change, went 88.3 s to 68.4 s in it). No ledger number changed in any design
(1e-9, every run). Warm rebuild after the first new build: 3.6 s, 8 of 8 from the cache.

Measured 2026-12-03 23:03-23:46 (seventh session), the README's command (no thread variables set), alone, 80622ea
against dac3327 (compute slots, ``glidectl.report.slots``: at most ``--jobs`` processes compute, first come first
served, on a pool of 2 x jobs design workers), in both orders (base2 then dac3327 run 1, two runs apart;
dac3327 run 2 then base3). A design's time now includes its waits for slots (ch7_ctol waits behind
roa_certification's parts), so compare the totals:

=====================  ==========  ==========  ==========  ==========
design                 80622ea 2   dac3327 1   dac3327 2   80622ea 3
=====================  ==========  ==========  ==========  ==========
ch2_longitudinal       8.0 s       8.0 s       6.7 s       8.4 s
ch4_phugoid            3.6 s       3.1 s       2.8 s       3.9 s
ch5_singular_pert.     9.8 s       9.5 s       8.3 s       9.6 s
ch6_controllers        21.4 s      19.1 s      17.1 s      32.0 s
ch7_ctol               107.2 s     379.2 s     376.2 s     108.7 s
ch8_helix              71.4 s      40.4 s      45.8 s      66.8 s
slocum_dive_cycle      220.1 s     127.5 s     130.6 s     198.0 s
roa_certification      420.7 s     395.3 s     385.1 s     417.8 s
end to end (wall)      435.2 s     401.0 s     389.9 s     426.5 s
user + system CPU      863.4 s     780.9 s     766.8 s     847.3 s
=====================  ==========  ==========  ==========  ==========

Wall 0.92 and 0.91, CPU 0.90 and 0.91: four single-threaded processes time-sliced on two cores (two designs with
their parts pools) cost about 10 % more CPU than two, and the build now idles about 10 s (wall minus CPU / 2) against
about 5 s. No ledger number changed (1e-9, every run). The FIFO slots on a pool of jobs design workers (bf2b3f8)
gave 446.6 s and 418.6 s in the same hour: a design waiting for its parts then held back the designs queued behind it.

Measured 2026-12-04 03:25-04:20 (eighth session), the README's command (no thread variables set), alone, not paired
(so not a speed comparison): f187741 421.5 s (CPU 825 s); 2742e85 with only its Clarabel pin 431.7 s (CPU 845 s);
2742e85 (Clarabel and BLAS held to one thread in the ROA layer) with ``--jobs 1``, a serial build in the CLI process
with the libraries' default threads: 760.8 s (CPU 780 s), and every ledger number of the 8 designs bitwise equal to
the ``--jobs 2`` build with the Clarabel pin only. Before the pins a serial build's ROA numbers differed from a pool
build's (the saturated user glider's SOS volume by 5 %).

Measured 2026-12-04 05:52-07:03 (ninth session, a fresh machine), the README's command (no thread variables set),
73dce59 (the large ROA programs matched modulo the angle equalities, the moment route's V step at steering
tolerances with its sample equations eliminated first) against 1574fa3: alone, new then base then new; then side
by side (``--jobs 2`` each, 4 processes on 2 cores):

=====================  ==========  ==========  ==========  ==========  ==========
design                 alone 73d.  alone 157.  alone 73d.  pair 157.   pair 73d.
=====================  ==========  ==========  ==========  ==========  ==========
ch2_longitudinal       6.8 s       9.3 s       7.0 s       16.9 s      18.9 s
ch4_phugoid            3.0 s       3.7 s       2.8 s       6.8 s       8.9 s
ch5_singular_pert.     8.0 s       9.7 s       9.4 s       17.4 s      19.1 s
ch6_controllers        18.2 s      25.6 s      19.6 s      40.4 s      45.0 s
ch7_ctol               337.9 s     397.9 s     380.9 s     787.9 s     763.6 s
ch8_helix              40.0 s      46.0 s      62.1 s      99.6 s      99.6 s
slocum_dive_cycle      118.0 s     133.7 s     155.0 s     274.9 s     277.6 s
roa_certification      345.7 s     413.3 s     390.9 s     795.6 s     774.5 s
end to end (wall)      350.3 s     418.8 s     397.4 s     804.8 s     784.5 s (ratio 0.975)
user + system CPU      691 s       820 s       784 s       803 s       767 s (0.955)
=====================  ==========  ==========  ==========  ==========  ==========

The same code took 350.3 s and 397.4 s alone an hour apart (CPU 691 s and 784 s): the machine's drift, larger than
the change. The pair is the comparison: 0.975 of the wall time, 0.955 of the CPU. Inside it the CTOL certificate
took 95.3 s against 196.9 s; the other certificates (degree 2, Clarabel-centred, below ``QUOTIENT_MIN_BLOCK``) are
the same programs. No ledger number changed in any design (every ``numbers.json``, 1e-9 relative, timings left
out) except the CTOL certificate's verification text: the same volume 0.0021606, its final Gram check with slack
3.71e-05 against 1.97e-05 (margin 1.45e+08 against 2.32). The cold build stays about 1.2-1.3 times the 300 s
target: the saturated user glider's SOS path (about 130 s of CPU), the unsaturated one (about 80 s, shared with
slocum_dive_cycle), the three full-glider certificates (about 30 s each) and ch7_ctol's simulations are the rest.

Profiled 2026-12-04 10:10-11:00 (tenth session), each part alone in one process with one thread (cProfile adds
about 10-30 %), to see where the remaining CPU goes. The profile is flat: no single function holds more than a
tenth of the build.

=============================  =======  ===================================================================
part                           s        where the time goes
=============================  =======  ===================================================================
user glider, pump saturated    150.6    SDP 98.5 s: 8 V steps by Clarabel (6-7 s each, 30 iterations of ~0.2 s:
(roa_certification, SOS path)           the dense Hessian block of the 54 x 54 decrease Gram matrix, 1485^2),
                                        8 centring programs by Clarabel (2.8 s), 19 level programs on the moment
                                        route (1.2 s); remainder-box search 18 s, containment/sampling 16 s,
                                        simulations 14 s, surrogates 9 s
chapter-6 buoyancy loop        52.9 p   Clarabel 14 s (113 solves, 78 of them the LMI path's), simulations
                                        10.7 s, surrogates 9.8 s, radii bisection 8.3 s, verification 7.3 s
full glider K_M = -100         37.8 p   Clarabel 22 s (16 solves), simulations 10 s (5.3 s the design's
                                        simulated region)
ch7_ctol printed-gains run     47.7     LSODA through solve_ivp, 400 replanning intervals; about 10 us per
                                        right-hand side and 15 us of solver overhead per step
ch8_helix (whole design)       39.6 p   helix existence scan 20 s, the eight parameter sweeps 13 s
ch6_controllers (whole)        30.1 p   batch integrations of compare_controllers 24.6 s
=============================  =======  ===================================================================

(p: under the profiler.) What was tried on them and not kept (details in ``bench/bench_roa_retry.py``):

- **Clarabel settings.** Iterative refinement off, at one step, or at reltol 1e-10 saves 20-40 % of a V step, but
  moves every Clarabel-centred path: the saturated user glider then lost its second remainder-box round (volume
  4.7e-15 against 3.48e-12) and, refinement off for the V steps only, the K_M = -100 glider's V steps steered to
  sets 1e7 times smaller than the starting V's (its certificate fell from 0.169 to 4.0e-6, the starting V's).
  Chordal decomposition off: bitwise the same, no faster.
- **The V steps of the degree-2 loops on the moment route** (routing by the equations left after the sample
  equations are eliminated): 3.3 s against 6.6 s per V step, but every V step of the user glider, retried or not,
  ended on a point whose level is -1.5e-9 to -4.5e-8 (volume 5.3e-16).
- **Stiff methods for ch7_ctol's printed gains.** The pitch loop's eigenvalues at the level glide are
  -125 +- 1522i: the ringing after each replanning (period 4.1 ms, time constant 8 ms, about 24 periods before it
  has decayed to e^-12.5 at the end of the 0.1 s interval) fills every interval, so any method has to follow it at
  the run's tolerance: it is oscillatory, not stiff. Radau (with the exact complex-step Jacobian) took 530.6 s
  against LSODA's 47.7 s (the same max error 3.3045 m to 6 digits), BDF stopped at t = 0.3 s (step size
  underflow). LSODA stays.
- **Vectorized polynomial evaluation** (all terms at once, the sums in the same order: bitwise the same): 7-11
  times slower than the per-term loop from 2000 points up.

What did land: the retried V step (``glidectl.roa.certify.RETRY_CENTER``), which makes the alternation survive a V
step whose V has no positive level (the perturbed runs above), and which changes no number of this build (no step
fails there), and ``_contains`` lifting each point once (bitwise the same). Measured 2026-12-04, the README's
command (no thread variables set), 4185e78 alone at 11:27-11:33, then 4185e78 against 8acf854 side by side at
11:35-11:49 (``--jobs 2`` each, 4 processes on 2 cores):

=====================  ==========  ==========  ==========
design                 alone 418.  pair 418.   pair 8ac.
=====================  ==========  ==========  ==========
ch2_longitudinal       6.7 s       19.1 s      20.0 s
ch4_phugoid            2.8 s       8.0 s       10.0 s
ch5_singular_pert.     7.7 s       20.2 s      20.0 s
ch6_controllers        18.0 s      49.1 s      51.0 s
ch7_ctol               334.4 s     751.6 s     758.3 s
ch8_helix              42.4 s      84.6 s      84.7 s
slocum_dive_cycle      123.2 s     271.2 s     275.9 s
roa_certification      340.8 s     809.8 s     813.9 s
end to end (wall)      345.8 s     818.6 s     822.8 s (ratio 0.995)
user + system CPU      682.6 s     810.0 s     820.7 s (0.987)
=====================  ==========  ==========  ==========

Every ledger number of the three builds is the same (288 numbers, 1e-9 relative, timings left out). The warm
rebuild after the alone build: 2.4 s, 8 of 8 from the cache. The cold build is 1.15 times the 300 s target.

**Before and after the issue** (2026-12-04 13:50-15:25, one run, each build alone on the idle machine). Before is
75a826a, the code the issue was filed against, built with the README's command of its time (``glidectl report
all``: serial, no cache). Its roa_certification stopped after 1671 s in the CTOL part ("x must hold real numbers,
got an array of dtype complex128", the complex-step Hessian of ``ctol_lyapunov``), so that design was built again
with 93fca80 (the one-line fix, picked onto 75a826a) at 14:39-15:05. After is 6dda53f with ``--jobs 2`` (the
README's command now, 13:50-13:57) and with ``--jobs 1`` (serial like the baseline, 15:05-15:16; the tree then
also held the warning fix of 20c1b18, which changes no number). Seconds per design ("done in"; in the ``--jobs 2``
build, measured in its worker beside the others, waits for slots included):

==================  ====================  =============================  ==============================
design              75a826a serial        6dda53f --jobs 1               6dda53f --jobs 2
==================  ====================  =============================  ==============================
ch2_longitudinal    8.9 s                 8.6 s                          10.0 s
ch4_phugoid         3.2 s                 3.4 s                          5.0 s
ch5_singular_pert.  25.1 s                8.7 s                          8.3 s
ch6_controllers     431.9 s               18.2 s                         19.6 s
ch7_ctol            215.4 s               75.5 s                         394.6 s (slot waits included)
ch8_helix           40.5 s                29.1 s                         55.3 s
slocum_dive_cycle   (not a design yet)    43.9 s (read the certificate)  147.1 s (computed it)
roa_certification   1536.2 s (6 cases)    485.6 s (11 parts)             404.1 s (read the certificate)
end to end (wall)   about 2265 s          676.0 s                        412.5 s (6 min 52 s)
user + system CPU   2229.9 s (roa alone)  695.2 s                        806.4 s
peak RSS            2.26 GB               not measured                   0.80 GB
==================  ====================  =============================  ==============================

The after column does more: one design more (slocum_dive_cycle) and five more roa parts (the saturated loops, among
them the user glider's two 8-state SOS certificates). A second cold ``--jobs 2`` build (20c1b18, 15:16-15:22) took
375.8 s, CPU 737.1 s; the warm rebuild after it 2.9 s, 8 of 8 from the cache. The ``--jobs 2`` build spends 16 %
more CPU than the serial one (806 against 695 s): process starts and two processes sharing the machine's two
cores. Numbers: the ``--jobs 1`` and ``--jobs 2`` builds agree on all 281 (1e-9 relative, timings left out).
Against 75a826a, ch2, ch4 and ch5 agree on every number; ch8's inverse designs moved by 1e-7 relative or less
and ch6's simulated differences by up to 5.1e-6 (the batch integrator of the ensembles; ch6's buoyancy final error
1.9e-11 -> 2.2e-11, rounding level); ch7's printed-gains run by up to 5.1e-6 (peak thrust) and its literal-gains
run stops at 12.4 s (0.646 m) instead of 30.1 s (0.708 m), the integrator sensitivity its ledger note states;
roa_certification's certificates moved with issue 17's SOS changes (CTOL volume 0.00441 -> 0.00216, the removed
residual artifact its ledger note explains; full glider K_M = -50 0.1151 -> 0.1543, K_M = -100 0.16986 -> 0.16866,
torque loop 0.14633 -> 0.14412, reduced glider area 11.544 -> 11.714).
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import pstats
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _one(name: str, quick: bool, profile: bool) -> dict:
    """Child process: cold, warm and (optionally) profiled build of one design."""
    import matplotlib

    import glidectl
    from glidectl.report import load_design
    from glidectl.report.parallel import build_designs

    matplotlib.use("Agg")  # the benchmark (not the library) picks the backend
    d = load_design(name, Path(glidectl.__file__).resolve().parents[2] / "designs")
    out: dict = {"design": name, "settings": "quick" if quick else "full"}
    with tempfile.TemporaryDirectory(prefix="bench-report-") as tmp:
        t0 = time.perf_counter()
        (res,) = build_designs([d], tmp, quick=quick, jobs=1, stream=io.StringIO())
        out["cold_s"] = time.perf_counter() - t0
        out["compute_s"] = res.seconds
        t0 = time.perf_counter()
        (hit,) = build_designs([d], tmp, quick=quick, jobs=1, stream=io.StringIO())
        out["warm_s"] = time.perf_counter() - t0
        out["warm_was_hit"] = hit.from_cache
        out["numbers"] = json.loads(res.files["numbers.json"])
    if profile:
        prof = cProfile.Profile()
        t0 = time.perf_counter()
        prof.runcall(d.report, lambda m: None, quick)
        out["profiled_s"] = time.perf_counter() - t0
        st = pstats.Stats(prof)
        rows = sorted(st.stats.items(), key=lambda kv: -kv[1][3])  # (cc, nc, tt, ct, callers)
        top = []
        for (fn, line, func), (_, nc, tt, ct, _) in rows:
            if func in ("<module>", "runcall", "<lambda>") and ct >= rows[0][1][3] * 0.99:
                continue  # the profiled call itself
            top.append({"function": f"{Path(fn).name}:{line}({func})", "calls": nc, "tottime_s": round(tt, 3),
                        "cumtime_s": round(ct, 3)})
            if len(top) == 10:
                break
        out["top_cumulative"] = top
    return out


def _run_child(name: str, quick: bool, profile: bool, src: Path | None = None) -> dict:
    """One design in a fresh process, with this checkout's glidectl or the one in ``src`` (its designs too)."""
    cmd = [sys.executable, __file__, "--child", name] + ([] if quick else ["--full"]) + (["--profile"] if profile
                                                                                          else [])
    env = dict(os.environ)
    if src is not None:
        env["PYTHONPATH"] = str(src)
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, env=env)
    if proc.returncode != 0:
        return {"design": name, "error": proc.stderr.strip().splitlines()[-1:] or ["?"]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _total(quick: bool) -> dict:
    with tempfile.TemporaryDirectory(prefix="bench-report-all-") as tmp:
        base = [sys.executable, "-m", "glidectl.cli", "report", "all", "--out", tmp] + (["--quick"] if quick else [])
        res = {}
        for label, extra in (("cold_s", ["--no-cache"]), ("warm_s", [])):
            t0 = time.perf_counter()
            proc = subprocess.run(base + extra, capture_output=True, text=True, cwd=ROOT)
            res[label] = time.perf_counter() - t0
            res[label.replace("_s", "_rc")] = proc.returncode
            res[label.replace("_s", "_summary")] = proc.stdout.strip().splitlines()[-1:] if proc.stdout else []
        res["jobs"] = os.cpu_count()
        return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--full", action="store_true", help="the designs' full settings (default: quick)")
    ap.add_argument("--designs", default="", help="comma-separated design names (default: all)")
    ap.add_argument("--profile", action="store_true", help="also profile each design (cProfile, top 10)")
    ap.add_argument("--no-total", action="store_true", help="skip the `glidectl report all` runs")
    ap.add_argument("--total-only", action="store_true", help="only the `glidectl report all` runs")
    ap.add_argument("--tag", default="", help="suffix of the results file")
    ap.add_argument("--baseline-src", default=None,
                    help="another checkout's src folder: each design is built with it too (its own designs/), "
                         "alternating with this checkout's, in the same run")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    quick = not args.full
    if args.child:
        print(json.dumps(_one(args.child, quick, args.profile)))
        return
    from glidectl.report import find_designs

    names = [] if args.total_only else [n for n in args.designs.split(",") if n] or list(find_designs(ROOT / "designs"))
    results = []
    base = Path(args.baseline_src).resolve() if args.baseline_src else None
    for name in names:
        if base is not None:
            b = _run_child(name, quick, False, base)
            b["design"] = f"{name} [baseline]"
            results.append(b)
            print(f"{name + ' [baseline]':<40} " + (f"ERROR {b['error']}" if "error" in b else
                                                    f"cold {b['cold_s']:8.1f} s  warm {b['warm_s']:6.2f} s"),
                  flush=True)
        r = _run_child(name, quick, args.profile, ROOT / "src")
        results.append(r)
        if "error" in r:
            print(f"{name:<40} ERROR {r['error']}", flush=True)
            continue
        print(f"{name:<40} cold {r['cold_s']:8.1f} s  warm {r['warm_s']:6.2f} s (hit: {r['warm_was_hit']})"
              + (f"  profiled {r['profiled_s']:8.1f} s" if "profiled_s" in r else ""), flush=True)
        for row in r.get("top_cumulative", []):
            print(f"    {row['cumtime_s']:8.2f} s  {row['calls']:>8}  {row['function']}")
    doc = {"settings": "quick" if quick else "full", "cpus": os.cpu_count(), "load_avg": os.getloadavg(),
           "baseline_src": str(base) if base else None,
           "python": sys.version.split()[0], "designs": results}
    if not args.no_total:
        doc["report_all"] = _total(quick)
        t = doc["report_all"]
        print(f"glidectl report all{' --quick' if quick else ''}: cold {t['cold_s']:.1f} s, warm {t['warm_s']:.1f} s")
    out = ROOT / "bench" / "results" / f"report_all{'_' + args.tag if args.tag else ''}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(doc, indent=1))
    print(out)


if __name__ == "__main__":
    main()
