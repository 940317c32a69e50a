#!/usr/bin/env python3
"""scripts/analysis/plot_realtime_curve.py on hand-made evaluation parts whose cost is known.

Setting "cheap": episodes 0 and 1, 10 s each, 50,000 rollout steps each (5,000 per simulated s),
juggles 4 and 8. Setting "dear": the same episodes, 20,000 steps per simulated s, juggles 10 and
12. At 10,000 rollout steps per wall-s they sit at 0.5 and 2.0 wall-s per simulated s.
A setting holding other episodes is refused. A recorded point ("old=@40000,3,2.5", a table row
whose folder is gone) is plotted at its numbers; a malformed one is refused. A point whose
rollout step costs half a reference step ("cheap=DIR~0.5") sits at half its steps. A plot of
recorded points only says how many starts they hold by --starts=N, and is refused without it;
--starts that disagrees with a folder is refused. The picture is 860 px wide, wider for a
legend line that would not fit.
"""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, '..', 'scripts', 'analysis', 'plot_realtime_curve.py')


def part(folder, episode, juggles, steps, seconds=10.0):
    os.makedirs(folder, exist_ok=True)
    base = os.path.join(folder, f'ep_{episode}')
    with open(base + '.jsonl', 'w') as f:
        f.write(json.dumps({'table': 'episode', 'episode': episode, 'juggles': juggles,
                            'seconds': seconds, 'outcome': 'time_limit'}) + '\n')
    with open(base + '.log', 'w') as f:
        f.write(f'episodes=1 planner_rollout_steps={steps} wall_s=99.0\n')


def main():
    with tempfile.TemporaryDirectory() as tmp:
        cheap, dear, other = (os.path.join(tmp, n) for n in ('cheap', 'dear', 'other'))
        part(cheap, 0, 4, 50000)
        part(cheap, 1, 8, 50000)
        part(dear, 0, 10, 200000)
        part(dear, 1, 12, 200000)
        part(other, 0, 10, 200000)
        part(other, 2, 12, 200000)
        out = os.path.join(tmp, 'curve.svg')
        run = subprocess.run([sys.executable, SCRIPT, out, '10000', 'title',
                              f'cheap={cheap}', f'dear={dear}'],
                             capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        lines = run.stdout.splitlines()
        assert lines[0] == ('cheap: rollout_steps_per_sim_s=5000 wall_s_per_sim_s_2cores=0.50 '
                            'mean=6.00 median=6'), lines
        assert lines[1] == ('dear: rollout_steps_per_sim_s=20000 wall_s_per_sim_s_2cores=2.00 '
                            'mean=11.00 median=11'), lines
        svg = open(out).read()
        assert svg.startswith('<svg') and svg.rstrip().endswith('</svg>'), svg[:80]
        for text in ('>1: cheap<', '>2: dear<', 'real time', '2 starts'):
            assert text in svg, text
        assert 'width="860"' in svg.splitlines()[0], svg.splitlines()[0]
        # A legend line too long for 860 px widens the picture (about 6 px per character).
        long_label = 'a setting with a label of about a hundred characters, ' + 'x' * 45
        wide = subprocess.run([sys.executable, SCRIPT, out, '10000', 'title',
                               f'{long_label}={cheap}'], capture_output=True, text=True)
        assert wide.returncode == 0, wide.stderr
        head = open(out).read().splitlines()[0]
        width = int(head.split('width="')[1].split('"')[0])
        assert width >= 620 + 14 + 6 * len('1: ' + long_label), head
        refused = subprocess.run([sys.executable, SCRIPT, out, '10000', 'title',
                                  f'cheap={cheap}', f'other={other}'],
                                 capture_output=True, text=True)
        assert refused.returncode != 0
        assert 'must share their starts' in refused.stderr, refused.stderr
        recorded = subprocess.run([sys.executable, SCRIPT, out, '10000', 'title',
                                   f'cheap={cheap}', 'old=@40000,3,2.5'],
                                  capture_output=True, text=True)
        assert recorded.returncode == 0, recorded.stderr
        assert recorded.stdout.splitlines()[1] == (
            'old: rollout_steps_per_sim_s=40000 wall_s_per_sim_s_2cores=4.00 mean=3.00 '
            'median=2.5'), recorded.stdout
        assert '>2: old<' in open(out).read()
        halved = subprocess.run([sys.executable, SCRIPT, out, '10000', 'title',
                                 f'dear={dear}~0.5', 'old=@40000,3,2.5~0.25'],
                                capture_output=True, text=True)
        assert halved.returncode == 0, halved.stderr
        assert halved.stdout.splitlines() == [
            'dear: rollout_steps_per_sim_s=10000 (its own 20000 at step cost 0.5) '
            'wall_s_per_sim_s_2cores=1.00 mean=11.00 median=11',
            'old: rollout_steps_per_sim_s=10000 (its own 40000 at step cost 0.25) '
            'wall_s_per_sim_s_2cores=1.00 mean=3.00 median=2.5'], halved.stdout
        bad_cost = subprocess.run([sys.executable, SCRIPT, out, '10000', 'title',
                                   f'dear={dear}~half'], capture_output=True, text=True)
        assert bad_cost.returncode != 0
        assert '~COST must be a number' in bad_cost.stderr, bad_cost.stderr
        only_recorded = [out, '10000', 'title', 'old=@40000,3,2.5', 'older=@80000,5,5']
        counted = subprocess.run([sys.executable, SCRIPT, '--starts=20'] + only_recorded,
                                 capture_output=True, text=True)
        assert counted.returncode == 0, counted.stderr
        assert '20 starts' in open(out).read()
        uncounted = subprocess.run([sys.executable, SCRIPT] + only_recorded,
                                   capture_output=True, text=True)
        assert uncounted.returncode != 0
        assert '--starts=N' in uncounted.stderr, uncounted.stderr
        disagreeing = subprocess.run([sys.executable, SCRIPT, '--starts=3', out, '10000',
                                      'title', f'cheap={cheap}'], capture_output=True, text=True)
        assert disagreeing.returncode != 0
        assert 'holds 2 episodes' in disagreeing.stderr, disagreeing.stderr
        malformed = subprocess.run([sys.executable, SCRIPT, out, '10000', 'title',
                                    f'cheap={cheap}', 'old=@40000,3'],
                                   capture_output=True, text=True)
        assert malformed.returncode != 0
        assert '@STEPS,MEAN,MEDIAN' in malformed.stderr, malformed.stderr
    print('ok')


if __name__ == '__main__':
    main()
