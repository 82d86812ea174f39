function flexmb_test_refused(run, id, words)
% Runs `run` and asserts that spacar() refuses it: the error identifier `id`, its message naming
% `words` (the option or reason). The spacar() option tests share it.
  try
    run();
  catch err
    assert(strcmp(err.identifier, id), '%s (%s)', err.identifier, err.message);
    assert(~isempty(strfind(err.message, words)), err.message);
    return;
  end
  error('accepted: expected %s', words);
end
