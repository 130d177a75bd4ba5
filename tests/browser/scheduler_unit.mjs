// The viewer's request scheduler (client/web/public/scheduler.js) in Node:
// "abort" lanes abort the task in flight and run the newest at once; "queue"
// lanes finish the task in flight and then run only the newest waiting one;
// errors reach the caller unless the task was superseded; whenIdle waits for
// every lane. Usage: node scheduler_unit.mjs
import { Scheduler } from '../../client/web/public/scheduler.js';

const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};
// A task that resolves to `value` after `ms`, or rejects with an AbortError
// when its signal is aborted first; it records what it saw.
const seen = [];
const task = (value, ms) => (signal) =>
  new Promise((resolve, reject) => {
    seen.push(`start ${value}`);
    const timer = setTimeout(() => resolve(value), ms);
    signal.addEventListener('abort', () => {
      clearTimeout(timer);
      seen.push(`abort ${value}`);
      reject(Object.assign(new Error('aborted'), { name: 'AbortError' }));
    });
  });

{
  const s = new Scheduler();
  const a = s.run('text', task('a', 50));
  const b = s.run('text', task('b', 10));
  const [ra, rb] = await Promise.all([a, b]);
  check(!ra.done && rb.done && rb.value === 'b', 'abort: the older is superseded, the newest gives its value');
  check(seen.join(',') === 'start a,abort a,start b', `abort: the older is aborted before the newer starts (${seen})`);
}
seen.length = 0;
{
  const s = new Scheduler();
  const a = s.run('exact', task('a', 30), { policy: 'queue' });
  const b = s.run('exact', task('b', 5), { policy: 'queue' });
  const c = s.run('exact', task('c', 5), { policy: 'queue' });
  check(s.busy('exact') && s.queued('exact'), 'queue: one in flight, one waiting');
  const [ra, rb, rc] = await Promise.all([a, b, c]);
  check(ra.done && ra.value === 'a', 'queue: the task in flight finishes');
  check(!rb.done, 'queue: an older waiting task is dropped');
  check(rc.done && rc.value === 'c', 'queue: the newest waiting task runs after it');
  check(seen.join(',') === 'start a,start c', `queue: b never started (${seen})`);
}
{
  const s = new Scheduler();
  let error = null;
  try {
    await s.run('surface', async () => {
      throw new Error('422: degenerate');
    });
  } catch (e) {
    error = e;
  }
  check(error?.message === '422: degenerate', "a task's own error reaches the caller");
  check(!s.busy(), 'the lane is free after an error');
}
{
  const s = new Scheduler();
  let idle = false;
  s.run('live', task('x', 20), { policy: 'queue' });
  s.run('mark', task('y', 40));
  const waited = s.whenIdle().then(() => (idle = true));
  await new Promise((r) => setTimeout(r, 25));
  check(!idle && s.busy(), 'whenIdle waits while any lane works');
  await waited;
  check(idle && !s.busy(), 'whenIdle resolves when every lane is done');
  await s.whenIdle();
  check(true, 'whenIdle resolves at once when idle');
}
{
  const s = new Scheduler();
  const a = s.run('upload', task('a', 30), { policy: 'queue' });
  const b = s.run('upload', task('b', 30), { policy: 'queue' });
  s.cancel('upload');
  const [ra, rb] = await Promise.all([a, b]);
  check(!ra.done && !rb.done && !s.busy(), 'cancel aborts the task in flight and drops the waiting one');
}
if (failures.length) {
  console.error(`${failures.length} failed`);
  process.exit(1);
}
console.log('scheduler: all checks passed');
