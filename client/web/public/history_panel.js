// Undo and redo. Ctrl+Z (Cmd+Z) undoes an edit of the surface's control
// points or of the placement (moved, scaled, rotated, fitted), Ctrl+Shift+Z
// or Ctrl+Y redoes it; so do the header's buttons. A step is an exact result
// shown after an edit: the surface's spec and the placement (with the sheet
// it is on). Choosing another model, preset or grid starts the history anew.
import { $ } from './dom.js';
import { EditHistory } from './edit_history.js';

export function installHistoryPanel(page) {
  const { store, scheduler, sheetView, modelView } = page;
  const history = new EditHistory({ derived: ['placementSheet'] });
  page.history = () => ({ back: history.back.length, ahead: history.ahead.length });

  const editStep = () => {
    const s = store.state;
    return { spec: s.spec, placement: s.placement, placementSheet: s.placementSheet };
  };

  function showHistory() {
    $('undo').disabled = !history.canUndo();
    $('redo').disabled = !history.canRedo();
  }

  // An exact result is on screen (`specSent`: the spec it was asked for,
  // JSON): the history's new start, or its next step where something was
  // edited. Not while an edit goes on or a newer result is on its way: that
  // one settles it.
  page.settleHistory = (specSent) => {
    const s = store.state;
    if (sheetView.drag || modelView.drag || scheduler.queued('exact') || JSON.stringify(s.spec) !== specSent) {
      return;
    }
    if (s.historyReset) history.reset(editStep());
    else if (s.edited) history.record(editStep());
    store.dispatch('historySettled');
    showHistory();
  };

  // The page as `step` had it: the preview at once (the field moved to its
  // control points, as a drag does), then its surface and exact result.
  function restoreStep(step) {
    const version = store.state.specVersion;
    store.dispatch('stepRestored', step);
    showHistory();
    if (store.state.specVersion === version) {
      page.showLivePreview();
      page.scheduleDeform(0);
      return;
    }
    const spec = store.state.spec;
    modelView.setControlPoints(spec.kind === 'bezier' ? spec.control_points : []);
    page.showControlPoint();
    page.showMovedField();
    page.refreshSurface(null);
  }

  function undoEdit() {
    if (sheetView.drag || modelView.drag || store.state.historyReset) return;
    // An edit not settled yet (a wheel's, within its 150 ms) goes back to the
    // last step; else the step before it.
    const step = store.state.edited ? history.currentStep() : history.undo();
    if (step) restoreStep(step);
  }

  function redoEdit() {
    if (sheetView.drag || modelView.drag || store.state.historyReset) return;
    const step = history.redo();
    if (step) restoreStep(step);
  }

  $('undo').addEventListener('click', undoEdit);
  $('redo').addEventListener('click', redoEdit);
  document.addEventListener('keydown', (e) => {
    if (!(e.ctrlKey || e.metaKey) || e.altKey) return;
    // Text and number fields keep their own undo.
    const t = e.target;
    if (t && (t.tagName === 'TEXTAREA' || (t.tagName === 'INPUT' && ['text', 'number', 'search'].includes(t.type))))
      return;
    const key = e.key.toLowerCase();
    if (key === 'z' && !e.shiftKey) undoEdit();
    else if ((key === 'z' && e.shiftKey) || key === 'y') redoEdit();
    else return;
    e.preventDefault();
  });
}
