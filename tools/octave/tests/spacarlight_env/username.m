function u = username()
% Stand-in for a variable SPACAR Light sets only on Windows (getenv('username')) and macOS
% (getenv('USER')): on Linux its .dat header line reads this function instead.
  u = getenv('USER');
end
